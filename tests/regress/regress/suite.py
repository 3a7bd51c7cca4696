"""Suite files: JSON with shared presets and cases (tests/regress/README.md, "Suite files")."""
import json
import os
import re

# Engine renderers: stock ones are loaded by name; the rest are presets of our module.
STOCK_RENDERERS = {"opengl1", "opengl2", "vulkan"}
GAME_PRESETS = {"lightmap", "direct", "path", "reference"}
SCENE_INTEGRATORS = {"lightmap", "direct", "path"}
COMPARE_MODES = {"exact", "noise", "perceptual"}

# Defaults of every case; a preset overrides them, a case overrides its preset.
DEFAULTS = {
    "size": [640, 360],
    "spp": None,          # None: the renderer's own default
    "seed": 0,
    "threads": 0,         # 0: all cores (captures must not depend on it)
    "frames": 1,          # pa-render: frames accumulated
    "cvars": {},          # engine: +set NAME VALUE
    "options": {},        # pa-render: --NAME VALUE (bounces, clamp, tonemap, exposure, ...)
    "compare": {"mode": "perceptual"},
    "timeout": 600,
    "capture_only": False,  # captured for other cases' 'against', compared with nothing itself
    "game_seed": 1,       # engine: the C library's rand() seed (pa_fixed_rand.so); None = the engine's own
}
COMPARE_DEFAULTS = {"alpha": 0.01, "min_pass": 0.9975, "flip_threshold": 0.1, "fail_fraction": 0.01}
NAME_RE = re.compile(r"^[A-Za-z0-9_.-]+$")


class SuiteError(Exception):
    """A suite file that cannot be used (the message names the file and the case)."""


def _merge(base, over):
    out = dict(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        else:
            out[key] = value
    return out


def parse_override(text):
    """'key=value' from --set: value is JSON when it parses, else a string; dotted keys nest."""
    if "=" not in text:
        raise SuiteError(f"--set {text!r}: expected KEY=VALUE")
    key, raw = text.split("=", 1)
    try:
        value = json.loads(raw)
    except ValueError:
        value = raw
    for part in reversed(key.split(".")[1:]):
        value = {part: value}
    return key.split(".")[0], value


def load_suite(path, overrides=()):
    """Reads a suite file; returns {"name", "path", "references", "cases": [resolved case dicts]}."""
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        raise SuiteError(f"{path}: {e}")
    base_dir = os.path.dirname(os.path.abspath(path))
    presets = data.get("presets", {})
    cases, seen = [], set()
    for raw in data.get("cases", []):
        name = raw.get("name", "")
        where = f"{path}: case {name!r}"
        if not NAME_RE.match(name) or name in seen:
            raise SuiteError(f"{where}: names must be unique and use only A-Z a-z 0-9 _ . -")
        seen.add(name)
        case = dict(DEFAULTS)
        for preset_name in ([raw["preset"]] if isinstance(raw.get("preset"), str) else raw.get("preset", [])):
            if preset_name not in presets:
                raise SuiteError(f"{where}: unknown preset {preset_name!r}")
            case = _merge(case, presets[preset_name])
        case = _merge(case, {k: v for k, v in raw.items() if k != "preset"})
        for text in overrides:
            key, value = parse_override(text)
            case = _merge(case, {key: value})
        case["compare"] = _merge(COMPARE_DEFAULTS, case["compare"])
        cases.append(_validate(case, where, base_dir))
    names = {c["name"] for c in cases}
    for c in cases:
        if c.get("against") and c["against"] not in names:
            raise SuiteError(f"{path}: case {c['name']!r}: 'against' names no case of the suite")
    refs = data.get("references", "references/" + data.get("name", "suite"))
    return {"name": data.get("name", os.path.splitext(os.path.basename(path))[0]), "path": os.path.abspath(path),
            "references": os.path.normpath(os.path.join(base_dir, refs)), "cases": cases}


def _resolve(path, base_dir):
    if os.path.isabs(path):
        return path
    local = os.path.normpath(os.path.join(base_dir, path))
    return local if os.path.exists(local) else os.path.abspath(path)


def _validate(case, where, base_dir):
    kinds = [k for k in ("scene", "demo", "map") if case.get(k)]
    if len(kinds) != 1:
        raise SuiteError(f"{where}: give exactly one of scene, demo, map")
    case["kind"] = kinds[0]
    renderer = case.get("renderer")
    if case["kind"] == "scene":
        case["renderer"] = renderer or "path"
        if case["renderer"] not in SCENE_INTEGRATORS:
            raise SuiteError(f"{where}: scene renderer must be one of {sorted(SCENE_INTEGRATORS)}")
        case["scene"] = _resolve(case["scene"], base_dir)
        case["frame_names"] = ["frame"]
    else:
        if renderer not in STOCK_RENDERERS | GAME_PRESETS:
            raise SuiteError(f"{where}: renderer must be a stock one {sorted(STOCK_RENDERERS)} or a preset {sorted(GAME_PRESETS)}")
        if case["kind"] == "demo":
            ticks = case.get("ticks")
            if not ticks or any(not isinstance(t, int) or t <= 0 for t in ticks) or ticks != sorted(set(ticks)):
                raise SuiteError(f"{where}: ticks must be increasing positive integers")
            if case["demo"].endswith(".dm_71"):
                case["demo"] = _resolve(case["demo"], base_dir)
            case["frame_names"] = [f"tick_{t:04d}" for t in ticks]
        else:
            views = case.get("views")
            if not views or not all(re.match(r"^-?[0-9.]+ -?[0-9.]+ -?[0-9.]+ -?[0-9.]+$", v) for v in views):
                raise SuiteError(f"{where}: views must be 'X Y Z YAW' strings")
            case["frame_names"] = [f"view_{i + 1}" for i in range(len(views))]
    if case["game_seed"] is not None and not (isinstance(case["game_seed"], int) and case["game_seed"] >= 0):
        raise SuiteError(f"{where}: game_seed must be a non-negative integer or null")
    size = case["size"]
    if not (isinstance(size, list) and len(size) == 2 and all(isinstance(s, int) and s > 0 for s in size)):
        raise SuiteError(f"{where}: size must be [WIDTH, HEIGHT]")
    mode = case["compare"].get("mode")
    if mode not in COMPARE_MODES:
        raise SuiteError(f"{where}: compare.mode must be one of {sorted(COMPARE_MODES)}")
    if mode == "noise" and case["renderer"] in STOCK_RENDERERS:
        raise SuiteError(f"{where}: compare.mode noise needs the film's EXR (pa-render or a preset of our module)")
    return case


def groups(cases):
    """Cases joined by 'against' stay together: returns lists of cases in suite order."""
    index = {c["name"]: i for i, c in enumerate(cases)}
    parent = list(range(len(cases)))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i, c in enumerate(cases):
        if c.get("against"):
            parent[find(i)] = find(index[c["against"]])
    out = {}
    for i in range(len(cases)):
        out.setdefault(find(i), []).append(cases[i])
    return sorted(out.values(), key=lambda g: index[g[0]["name"]])


def shard(cases, spec):
    """'K/N' (1 <= K <= N): the K-th of N shards, taking every N-th group of cases."""
    m = re.match(r"^(\d+)/(\d+)$", spec or "")
    if not m or not 1 <= int(m.group(1)) <= int(m.group(2)):
        raise SuiteError(f"--shard {spec!r}: expected K/N with 1 <= K <= N")
    k, n = int(m.group(1)), int(m.group(2))
    return [c for i, g in enumerate(groups(cases)) if i % n == k - 1 for c in g]
