#!/usr/bin/env bash
# CTest regress.game: suites/game_ci.json on the real engine under Xvfb, at the same demo ticks of
# dm1_ffa: lightmap against opengl1 (perceptual); path and direct against the reference preset
# (noise-aware, from the module's film EXRs); path with 1 thread identical to path with 2.
# Usage: game_test.sh BUILD_DIR COMPARE_TOOL. Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../../fidelity/engine_env.sh"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
out="$(mktemp -d /tmp/pa-regress-game.XXXXXX)"
trap 'rm -rf "$out"' EXIT
set +e
python3 "$here/../pa-regress" check "$here/../suites/game_ci.json" --out "$out" --build "$1" --compare "$2"
status=$?
set -e
python3 - "$out/summary.json" <<'PY'
import json, sys
for c in json.load(open(sys.argv[1]))["cases"]:
    for f in c["frames"]:
        fig = f.get("figures")
        if fig and "noise" in fig:
            n = fig["noise"]
            scales = ", ".join(f"{s['failed_tiles']}/{s['tiles']} {'tiles' if s['tile'] else 'image'} (max |z| {s['max_abs_z']:.2f}"
                               f" of {s['z_threshold']:.2f})" for s in n["tile_scales"])
            print(f"{c['name']} {f['name']}: {f['status']} noise: {n['failed_pixels']} of {n['pixels']} pixels beyond "
                  f"|z| {n['z_threshold']:.2f}; {scales}")
        elif fig:
            print(f"{c['name']} {f['name']}: {f['status']} {'identical ' if fig.get('identical') else ''}PSNR "
                  f"{fig['psnr']:.2f} dB SSIM {fig['ssim']:.3f} FLIP mean {fig['flip_mean']:.3f}, "
                  f"{100 * fig['flip_fail_fraction']:.1f} % above {fig['flip_threshold']}")
PY
exit $status
