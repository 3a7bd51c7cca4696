#!/usr/bin/env bash
# capture_view.sh OUT_DIR RENDERER MODULE MAP "X Y Z YAW" [more "X Y Z YAW" ...] -- [engine args...]
# Loads MAP with devmap in Debian's ioquake3 under xvfb-run, puts the player at each viewpoint
# (noclip + setviewpos: it stays there; no view bob, no gun, no 2D, 20 fps at most so that the stock renderer
# too has run the teleport through the server before the screenshot: both see the same picture)
# (CAPTURE_WAIT ticks there, default 40) and writes OUT_DIR/view_N.tga (N = 1, 2, ...) plus OUT_DIR/engine.log. RENDERER and MODULE as
# in capture_frames.sh. Used for views the demo never shows (fog volumes: tests/fidelity/README.md).
# CAPTURE_LOOK_DOWN=1: each view turns to look straight down (+lookdown until the pitch stops at
# 90 degrees) before its screenshot, for floors (setviewpos sets no pitch).
# CAPTURE_GAME_FILES (a folder, optional): its files are copied into the home path's baseoa, e.g.
# maps built by code (tests/fidelity/make_test_maps.cpp).
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/engine_env.sh"
out="$1"; renderer="$2"; module="$3"; map="$4"; shift 4
views=()
while [[ $# -gt 0 && "$1" != "--" ]]; do views+=("$1"); shift; done
[[ $# -gt 0 ]] && shift
width="${CAPTURE_WIDTH:-640}"; height="${CAPTURE_HEIGHT:-360}"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
[[ "$map" =~ ^[A-Za-z0-9_]+$ ]] || { echo "bad map name: $map"; exit 2; }
work="$(mktemp -d /tmp/pa-view.XXXXXX)"
trap 'rm -rf "$work"' EXIT
if [[ "$renderer" == pathtracer ]]; then pa_engine_prepare "$work" "$module"; else pa_engine_prepare "$work"; fi
[[ -n "${CAPTURE_GAME_FILES:-}" ]] && cp -r "$CAPTURE_GAME_FILES"/. "$work/home/baseoa/"
cfg="$(pa_engine_cfg "$work" view)"
printf 'set r_pt_pipeline 0\nwait 60\nnoclip\n' >"$cfg"
n=0
for view in "${views[@]}"; do
  [[ "$view" =~ ^-?[0-9.]+\ -?[0-9.]+\ -?[0-9.]+\ -?[0-9.]+$ ]] || { echo "bad view '$view' (X Y Z YAW)"; exit 2; }
  n=$((n + 1))
  printf 'setviewpos %s\n' "$view" >>"$cfg"
  [[ -n "${CAPTURE_LOOK_DOWN:-}" ]] && printf '+lookdown\nwait 30\n-lookdown\n' >>"$cfg"
  printf 'wait %d\nscreenshot view_%d\nviewpos\n' "${CAPTURE_WAIT:-40}" "$n" >>"$cfg"
done
printf 'wait 5\nquit\n' >>"$cfg"
mkdir -p "$out"
set +e
pa_engine_run "$work" "$out/engine.log" "${CAPTURE_TIMEOUT:-300}" "$width" "$height" "$renderer" \
  +set sv_pure 0 +set cg_drawGun 0 +set cg_draw2D 0 +set cg_bobup 0 +set cg_bobpitch 0 \
  +set cg_bobroll 0 +set con_notifytime -1 +set com_maxfps 20 "$@" +devmap "$map" +exec view.cfg
status=$?
set -e
cp "$work"/home/baseoa/screenshots/view_*.tga "$out/" 2>/dev/null || true
cp "$work"/home/baseoa/screenshots/view_*.exr "$out/" 2>/dev/null || true   # our module with r_pt_captureExr 1
if [[ $status -ne 0 ]]; then echo "engine exited with status $status (log: $out/engine.log)"; exit 1; fi
pa_engine_used_renderer "$out/engine.log" "$renderer" || { echo "renderer $renderer was not used (log: $out/engine.log)"; exit 1; }
for ((i = 1; i <= n; ++i)); do
  [[ -f "$out/view_$i.tga" ]] || { echo "view $i was not captured (log: $out/engine.log)"; exit 1; }
done
echo "captured $n views of $map with $renderer into $out"
