#!/usr/bin/env bash
# capture_demo.sh OUT_DIR RENDERER MODULE DEMO "T1 T2 ..." [engine args...]
# Plays DEMO (a name in the game's demos/, e.g. demo088-test1, or a path to a .dm_71 file) as a
# timedemo in Debian's ioquake3 under xvfb-run and writes OUT_DIR/tick_NNNN.tga at each command
# tick T (increasing; with our module and r_pt_captureExr 1 also tick_NNNN.exr), plus OUT_DIR/engine.log. Same-tick mechanism and RENDERER/MODULE as in
# tests/fidelity/capture_frames.sh (tests/fidelity/README.md, "How frames are made the same
# moment"); both are pa_capture_demo_ticks (engine_env.sh). Size: CAPTURE_WIDTH x CAPTURE_HEIGHT.
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../fidelity/engine_env.sh"
out="$1"; renderer="$2"; module="$3"; demo="$4"; ticks="$5"; shift 5
pa_capture_demo_ticks "$out" "$renderer" "$module" "$demo" tick "$ticks" "${CAPTURE_TIMEOUT:-600}" "$@"
echo "captured $(wc -w <<<"$ticks") frames of $demo with $renderer into $out"
