"""Captures one case's frames: pa-render for scenes, the real engine under Xvfb for game frames."""
import glob
import hashlib
import json
import os
import shutil
import subprocess
import time

from .suite import STOCK_RENDERERS

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # tests/regress
REPO = os.path.dirname(os.path.dirname(HERE))


class CaptureError(Exception):
    """A capture that did not produce its frames (the message says why; logs stay in the case folder)."""


class Tools:
    """Where the binaries of the build under test and the comparison tool live."""

    def __init__(self, build, compare=None):
        self.build = os.path.abspath(build)
        self.pa_render = os.path.join(self.build, "renderer/cli/pa-render")
        self.module = os.path.join(self.build, "port/engine_glue/renderer_pathtracer_x86_64.so")
        # The comparison tool need not come from the build under test (record --build OLD).
        self.compare = compare or os.environ.get("PA_REGRESS_COMPARE") or os.path.join(
            REPO, "build/tests/regress/pa-regress-compare")
        # Preloaded into the engine for a fixed rand() seed; like the comparison tool, from this
        # checkout's build (beside pa-regress-compare) unless PA_REGRESS_FIXED_RAND names it.
        self.fixed_rand = os.environ.get("PA_REGRESS_FIXED_RAND") or os.path.join(
            os.path.dirname(self.compare), "pa_fixed_rand.so")


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _run(cmd, log_path, timeout, env=None):
    with open(log_path, "a") as log:
        log.write("$ " + " ".join(cmd) + "\n")
        log.flush()
        try:
            return subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT, timeout=timeout, env=env).returncode
        except subprocess.TimeoutExpired:
            log.write(f"timed out after {timeout} s\n")
            return 124


def scene_command(case, tools, out_dir):
    w, h = case["size"]
    cmd = [tools.pa_render, case["scene"], "-o", os.path.join(out_dir, "frame.png"), "--exr",
           os.path.join(out_dir, "frame.exr"), "--width", str(w), "--height", str(h), "--integrator", case["renderer"],
           "--seed", str(case["seed"]), "--threads", str(case["threads"]), "--frames", str(case["frames"]),
           "--camera", str(case.get("camera", 0)), "-q"]
    if case["spp"] is not None:
        cmd += ["--spp", str(case["spp"])]
    for key, value in sorted(case["options"].items()):
        cmd += [f"--{key}"] + ([] if value is True else [str(value)])
    return cmd


def engine_args(case):
    """+set arguments of a game case: the preset and its sampling for our module, then the case's cvars."""
    args = []
    if case["renderer"] not in STOCK_RENDERERS:
        args += ["+set", "r_pt_preset", case["renderer"], "+set", "r_pt_seed", str(case["seed"]),
                 "+set", "r_pt_threads", str(case["threads"]), "+set", "r_pt_captureExr", "1"]
        if case["spp"] is not None:
            args += ["+set", "r_pt_spp", str(case["spp"])]
    for key, value in sorted(case["cvars"].items()):
        args += ["+set", key, str(value)]
    return args


def capture(case, tools, out_dir):
    """Writes out_dir/<frame>.png (and .exr for scenes) plus capture.json; returns the capture record."""
    if os.path.isdir(out_dir):
        shutil.rmtree(out_dir)
    os.makedirs(out_dir)
    log = os.path.join(out_dir, "capture.log")
    started = time.monotonic()
    if case["kind"] == "scene":
        if not os.access(tools.pa_render, os.X_OK):
            raise CaptureError(f"no pa-render at {tools.pa_render} (build target pa-render)")
        status = _run(scene_command(case, tools, out_dir), log, case["timeout"])
        if status != 0:
            raise CaptureError(f"pa-render exited with status {status} (log: {log})")
    else:
        renderer = case["renderer"] if case["renderer"] in STOCK_RENDERERS else "pathtracer"
        if renderer == "pathtracer" and not os.path.isfile(tools.module):
            raise CaptureError(f"no renderer module at {tools.module}")
        env = dict(os.environ, CAPTURE_WIDTH=str(case["size"][0]), CAPTURE_HEIGHT=str(case["size"][1]),
                   CAPTURE_TIMEOUT=str(case["timeout"]))
        if case["game_seed"] is not None:  # the game's effects draw from rand(): fix its seed
            if not os.path.isfile(tools.fixed_rand):
                raise CaptureError(f"no {tools.fixed_rand} (build target pa_fixed_rand) for game_seed")
            env.update(PA_ENGINE_PRELOAD=tools.fixed_rand, PA_FIXED_RAND_SEED=str(case["game_seed"]))
        raw = os.path.join(out_dir, "raw")
        if case["kind"] == "demo":
            cmd = [os.path.join(HERE, "capture_demo.sh"), raw, renderer, tools.module, case["demo"],
                   " ".join(str(t) for t in case["ticks"])] + engine_args(case)
        else:
            cmd = [os.path.join(os.path.dirname(HERE), "fidelity/capture_view.sh"), raw, renderer, tools.module,
                   case["map"]] + case["views"] + ["--"] + engine_args(case)
        status = _run(cmd, log, case["timeout"] + 60, env)
        if status == 77:
            raise CaptureError("skipped: the engine, the game data or xvfb-run are not installed")
        if status != 0:
            raise CaptureError(f"engine capture exited with status {status} (log: {log}, {raw}/engine.log)")
        for name in case["frame_names"]:
            if _run([tools.compare, "convert", os.path.join(raw, name + ".tga"), os.path.join(out_dir, name + ".png")],
                    log, 60) != 0:
                raise CaptureError(f"cannot convert {name}.tga to PNG (log: {log})")
            if os.path.isfile(os.path.join(raw, name + ".exr")):  # our module's film (r_pt_captureExr)
                os.replace(os.path.join(raw, name + ".exr"), os.path.join(out_dir, name + ".exr"))
        for tga in glob.glob(os.path.join(raw, "*.tga")):
            os.remove(tga)
    record = {"case": case["name"], "seconds": round(time.monotonic() - started, 3), "frames": {}}
    for name in case["frame_names"]:
        png = os.path.join(out_dir, name + ".png")
        if not os.path.isfile(png):
            raise CaptureError(f"frame {name} missing after capture (log: {log})")
        entry = {"png_sha256": sha256(png)}
        exr = os.path.join(out_dir, name + ".exr")
        if os.path.isfile(exr):
            entry["exr_sha256"] = sha256(exr)
        record["frames"][name] = entry
    settings = {k: case[k] for k in ("kind", "renderer", "size", "spp", "seed", "threads", "frames", "cvars", "options")}
    settings.update({k: case[k] for k in ("scene", "camera", "demo", "ticks", "map", "views") if k in case})
    if case["kind"] != "scene":
        settings["game_seed"] = case["game_seed"]
    for key in ("scene", "demo"):  # paths inside the repository are kept relative to its root
        if isinstance(settings.get(key), str) and settings[key].startswith(REPO + os.sep):
            settings[key] = os.path.relpath(settings[key], REPO)
    record["settings"] = settings
    with open(os.path.join(out_dir, "capture.json"), "w") as f:
        json.dump(record, f, indent=1, sort_keys=True)
    return record
