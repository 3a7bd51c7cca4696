#!/usr/bin/env python3
"""CTest regress.* end to end (tests/regress/README.md, "Tests"): pa-regress against the committed
references of the bundled scene. Usage: regress_test.py TEST BUILD_DIR COMPARE_TOOL
TEST: injected | seeds | update | shards. Exit 0 pass, 1 fail."""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.join(os.path.dirname(HERE), "pa-regress")
SUITE = os.path.join(os.path.dirname(HERE), "suites", "ci.json")
SCENE = os.path.normpath(os.path.join(HERE, "../../../renderer/cli/scenes/default_arena.gltf"))


def run(args, build, compare, expect=None):
    cmd = [sys.executable, TOOL] + args + ["--build", build, "--compare", compare]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    print("$ " + " ".join(cmd[1:]) + f"  -> exit {proc.returncode}")
    print(proc.stdout.strip())
    if proc.stderr.strip():
        print(proc.stderr.strip())
    if expect is not None and proc.returncode != expect:
        raise AssertionError(f"expected exit status {expect}, got {proc.returncode}")
    return proc.returncode


def summary(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def mutate(tmp, name, change):
    with open(SCENE) as f:
        gltf = json.load(f)
    change(gltf)
    path = os.path.join(tmp, name + ".gltf")
    with open(path, "w") as f:
        json.dump(gltf, f)
    return path


def material_colour(gltf):
    m = next(m for m in gltf["materials"] if m["name"] == "wall_plaster")
    m["pbrMetallicRoughness"]["baseColorFactor"] = [0.75, 0.65, 0.66, 1.0]  # green 0.72 -> 0.65


def light_removed(gltf):
    lamp = next(n for n in gltf["nodes"] if n.get("name") == "lamp")
    del lamp["extensions"]


def camera_one_pixel(gltf, width=64):
    """Turns the camera about its own up axis by the angle one pixel spans at the image centre."""
    node = next(n for n in gltf["nodes"] if n.get("name") == "camera")
    cam = gltf["cameras"][node["camera"]]["perspective"]
    half_h = math.tan(cam["yfov"] / 2) * cam["aspectRatio"]
    angle = math.atan(2 * half_h / width)
    qx, qy, qz, qw = node["rotation"]
    sx, sw = math.sin(angle / 2), math.cos(angle / 2)  # local yaw: q * (0, s, 0, c)
    node["rotation"] = [qx * sw - qz * sx, qy * sw + qw * sx, qz * sw + qx * sx, qw * sw - qy * sx]


def test_injected(build, compare, tmp):
    """Each injected regression fails arena_path (noise-aware) and is shown failing in the report."""
    regressions = {
        "material colour": ["--set", "scene=" + mutate(tmp, "colour", material_colour)],
        "light removed": ["--set", "scene=" + mutate(tmp, "nolamp", light_removed)],
        "camera moved by one pixel": ["--set", "scene=" + mutate(tmp, "camera", camera_one_pixel)],
        "biased integrator (clamp 1)": ["--set", "options.clamp=1"],
    }
    for i, (what, extra) in enumerate(regressions.items()):
        out = os.path.join(tmp, f"injected{i}")
        run(["check", SUITE, "--case", "arena_path", "--out", out] + extra, build, compare, expect=1)
        case = summary(out)["cases"][0]
        noise = case["frames"][0]["figures"]["noise"]
        tiles = ", ".join(f"{s['failed_tiles']}/{s['tiles']} tiles of {s['tile'] or 'whole image'} (max |z| {s['max_abs_z']:.1f})"
                          for s in noise["tile_scales"])
        print(f"{what}: {noise['failed_pixels']} of {noise['pixels']} pixels fail (allowed "
              f"{(1 - noise['min_pass_fraction']) * noise['pixels']:.1f}); {tiles}")
        assert case["status"] == "fail", what
        with open(os.path.join(out, "report.html")) as f:
            assert 'arena_path <span class=fail>fail</span>' in f.read(), what


def test_seeds(build, compare, tmp):
    """20 checks of the unchanged build with seeds 1..20 (independent noise against the reference of
    seed 0): no false alarm."""
    worst = 0
    for seed in range(1, 21):
        out = os.path.join(tmp, f"seed{seed}")
        run(["check", SUITE, "--case", "arena_path", "--case", "arena_direct", "--case", "arena_lightmap",
             "--out", out, "--set", f"seed={seed}"], build, compare, expect=0)
        for case in summary(out)["cases"]:
            worst = max(worst, case["frames"][0]["figures"]["noise"]["failed_pixels"])
    print(f"20 seeds x 3 cases: no false alarm; most failing pixels in one image: {worst}")


def test_update(build, compare, tmp):
    """--update rewrites a failing reference; the next check passes."""
    refs = os.path.join(tmp, "refs")
    shutil.copytree(os.path.join(os.path.dirname(HERE), "references", "ci"), refs)
    args = ["check", SUITE, "--refs", refs, "--case", "arena_direct", "--set", "options.clamp=0.5"]
    run(args + ["--out", os.path.join(tmp, "u1"), "--update"], build, compare, expect=1)
    assert summary(os.path.join(tmp, "u1"))["cases"][0].get("updated")
    run(args + ["--out", os.path.join(tmp, "u2")], build, compare, expect=0)


def strip(data):
    if isinstance(data, dict):
        return {k: strip(v) for k, v in data.items() if not k.endswith("seconds") and k not in ("shard", "merged_shards")}
    if isinstance(data, list):
        return [strip(v) for v in data]
    return data


def test_shards(build, compare, tmp):
    """Four shards run one after another, merged, equal the unsharded run, passing or failing."""
    whole, parts = os.path.join(tmp, "whole"), os.path.join(tmp, "parts")
    run(["check", SUITE, "--out", whole], build, compare, expect=0)
    for k in range(1, 5):
        run(["check", SUITE, "--out", parts, "--shard", f"{k}/4"], build, compare, expect=0)
    run(["merge", parts], build, compare, expect=0)
    assert strip(summary(whole)) == strip(summary(parts)), "merged shards differ from the unsharded run"
    # A regression in one shard: the merge reports it (exit 1) exactly as the unsharded run does.
    whole, parts = os.path.join(tmp, "whole-clamp"), os.path.join(tmp, "parts-clamp")
    clamp = ["--set", "options.clamp=1"]
    run(["check", SUITE, "--out", whole] + clamp, build, compare, expect=1)
    for k in range(1, 5):
        run(["check", SUITE, "--out", parts, "--shard", f"{k}/4"] + clamp, build, compare)
    run(["merge", parts], build, compare, expect=1)
    assert strip(summary(whole)) == strip(summary(parts)), "merged failing shards differ from the unsharded run"


def main():
    test, build, compare = sys.argv[1], os.path.abspath(sys.argv[2]), os.path.abspath(sys.argv[3])
    tmp = tempfile.mkdtemp(prefix="pa-regress-test.")
    try:
        {"injected": test_injected, "seeds": test_seeds, "update": test_update, "shards": test_shards}[test](build, compare, tmp)
    except AssertionError as e:
        print(f"FAIL: {e}")
        return 1
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("PASS")
    return 0


if __name__ == "__main__":
    sys.exit(main())
