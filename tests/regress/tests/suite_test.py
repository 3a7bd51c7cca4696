#!/usr/bin/env python3
"""CTest regress.suite: suite files (presets, overrides, validation) and shards (unittest)."""
import json
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from regress.suite import SuiteError, groups, load_suite, parse_override, shard  # noqa: E402


def write_suite(data):
    f = tempfile.NamedTemporaryFile("w", suffix=".json", delete=False)
    json.dump(data, f)
    f.close()
    return f.name


SCENE = {"scene": "scene.gltf"}


class SuiteTest(unittest.TestCase):
    def test_presets_apply_in_order_and_cases_override(self):
        path = write_suite({"presets": {"a": {"spp": 4, "size": [8, 8], "options": {"bounces": 2}},
                                        "b": {"spp": 16, "compare": {"mode": "noise"}}},
                            "cases": [{"name": "c", "preset": ["a", "b"], "options": {"clamp": 1}, **SCENE}]})
        case = load_suite(path)["cases"][0]
        self.assertEqual(case["spp"], 16)
        self.assertEqual(case["size"], [8, 8])
        self.assertEqual(case["options"], {"bounces": 2, "clamp": 1})
        self.assertEqual(case["compare"]["mode"], "noise")
        self.assertEqual(case["compare"]["min_pass"], 0.9975)  # default kept
        self.assertEqual(case["frame_names"], ["frame"])

    def test_overrides_parse_json_and_nest(self):
        self.assertEqual(parse_override("seed=3"), ("seed", 3))
        self.assertEqual(parse_override("options.clamp=0.5"), ("options", {"clamp": 0.5}))
        self.assertEqual(parse_override("scene=/tmp/x.gltf"), ("scene", "/tmp/x.gltf"))
        path = write_suite({"cases": [{"name": "c", **SCENE, "options": {"bounces": 3}}]})
        case = load_suite(path, ["options.clamp=1", "seed=9"])["cases"][0]
        self.assertEqual((case["options"], case["seed"]), ({"bounces": 3, "clamp": 1}, 9))

    def test_invalid_cases_are_refused(self):
        bad = [
            [{"name": "c"}],                                                  # no scene/demo/map
            [{"name": "c", **SCENE, "demo": "x"}],                            # two sources
            [{"name": "c", **SCENE}, {"name": "c", **SCENE}],                  # duplicate name
            [{"name": "c d", **SCENE}],                                       # bad name
            [{"name": "c", "demo": "x", "ticks": [80, 40], "renderer": "lightmap"}],  # ticks not increasing
            [{"name": "c", "demo": "x", "ticks": [40], "renderer": "nope"}],  # unknown renderer
            [{"name": "c", "map": "m", "views": ["1 2 3"], "renderer": "opengl1"}],  # view without yaw
            [{"name": "c", "demo": "x", "ticks": [40], "renderer": "opengl1", "compare": {"mode": "noise"}}],  # no film
            [{"name": "c", "demo": "x", "ticks": [40], "renderer": "path", "game_seed": -1}],
            [{"name": "c", **SCENE, "against": "missing"}],
            [{"name": "c", **SCENE, "preset": "missing"}],
        ]
        for cases in bad:
            with self.subTest(cases=cases), self.assertRaises(SuiteError):
                load_suite(write_suite({"cases": cases}))

    def test_game_cases_fix_the_rand_seed_and_presets_may_be_noise_aware(self):
        path = write_suite({"cases": [{"name": "a", "demo": "x", "ticks": [40], "renderer": "path",
                                       "compare": {"mode": "noise"}},
                                      {"name": "b", "demo": "x", "ticks": [40], "renderer": "opengl1", "game_seed": None}]})
        a, b = load_suite(path)["cases"]
        self.assertEqual((a["game_seed"], a["compare"]["mode"]), (1, "noise"))
        self.assertIsNone(b["game_seed"])

    def test_shards_partition_and_keep_against_groups_together(self):
        cases = [{"name": f"c{i}", **SCENE} for i in range(7)]
        cases[5]["against"] = "c1"
        suite = load_suite(write_suite({"cases": cases}))
        self.assertEqual([[c["name"] for c in g] for g in groups(suite["cases"])][1], ["c1", "c5"])
        names = [[c["name"] for c in shard(suite["cases"], f"{k}/3")] for k in (1, 2, 3)]
        self.assertEqual(sorted(n for part in names for n in part), sorted(c["name"] for c in cases))
        self.assertTrue(any({"c1", "c5"} <= set(part) for part in names))
        for spec in ("0/3", "4/3", "1-3", ""):
            with self.assertRaises(SuiteError):
                shard(suite["cases"], spec)


if __name__ == "__main__":
    unittest.main()
