#!/usr/bin/env bash
# CTest regress.game: suites/game_ci.json on the real engine under Xvfb: lightmap against opengl1,
# direct and path against the reference preset, at the same demo ticks of dm1_ffa (perceptual).
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
        if fig:
            print(f"{c['name']} {f['name']}: {f['status']} PSNR {fig['psnr']:.2f} dB SSIM {fig['ssim']:.3f} "
                  f"FLIP mean {fig['flip_mean']:.3f}, {100 * fig['flip_fail_fraction']:.1f} % above {fig['flip_threshold']}")
PY
exit $status
