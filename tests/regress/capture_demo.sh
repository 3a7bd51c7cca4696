#!/usr/bin/env bash
# capture_demo.sh OUT_DIR RENDERER MODULE DEMO "T1 T2 ..." [engine args...]
# Plays DEMO (a name in the game's demos/, e.g. demo088-test1, or a path to a .dm_71 file) as a
# timedemo in Debian's ioquake3 under xvfb-run and writes OUT_DIR/tick_NNNN.tga at each command
# tick T (increasing; with our module and r_pt_captureExr 1 also tick_NNNN.exr), plus OUT_DIR/engine.log. Same-tick mechanism and RENDERER/MODULE as in
# tests/fidelity/capture_frames.sh (tests/fidelity/README.md, "How frames are made the same
# moment"). Size: CAPTURE_WIDTH x CAPTURE_HEIGHT. Exit 77 when the engine, the game data or
# xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/../fidelity/engine_env.sh"
out="$1"; renderer="$2"; module="$3"; demo="$4"; ticks="$5"; shift 5
width="${CAPTURE_WIDTH:-640}"; height="${CAPTURE_HEIGHT:-360}"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }

work="$(mktemp -d /tmp/pa-regress-demo.XXXXXX)"
trap 'rm -rf "$work"' EXIT
if [[ "$renderer" == pathtracer ]]; then pa_engine_prepare "$work" "$module"; else pa_engine_prepare "$work"; fi
if [[ "$demo" == *.dm_71 ]]; then
  [[ -f "$demo" ]] || { echo "no demo file $demo"; exit 2; }
  mkdir -p "$work/home/baseoa/demos"
  cp "$demo" "$work/home/baseoa/demos/pa_regress.dm_71"
  demo=pa_regress
fi
[[ "$demo" =~ ^[A-Za-z0-9_.-]+$ ]] || { echo "bad demo name: $demo"; exit 2; }
pa_tick_screenshots_cfg "$(pa_engine_cfg "$work" capture)" tick "$ticks" || exit 2

mkdir -p "$out"
set +e
pa_engine_run "$work" "$out/engine.log" "${CAPTURE_TIMEOUT:-600}" "$width" "$height" "$renderer" \
  +set timedemo 1 +set com_maxfps 0 +set cg_drawFPS 0 +set con_notifytime -1 "$@" +demo "$demo" +exec capture.cfg
status=$?
set -e
cp "$work"/home/baseoa/screenshots/tick_*.tga "$out/" 2>/dev/null || true
cp "$work"/home/baseoa/screenshots/tick_*.exr "$out/" 2>/dev/null || true   # r_pt_captureExr 1
if [[ $status -ne 0 ]]; then echo "engine exited with status $status (log: $out/engine.log)"; exit 1; fi
pa_engine_used_renderer "$out/engine.log" "$renderer" || { echo "renderer $renderer was not used (log: $out/engine.log)"; exit 1; }
for tick in $ticks; do
  [[ -f "$out/$(printf 'tick_%04d.tga' "$tick")" ]] || { echo "tick $tick was not captured (log: $out/engine.log)"; exit 1; }
done
echo "captured $(wc -w <<<"$ticks") frames of $demo with $renderer into $out"
