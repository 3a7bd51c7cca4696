#!/usr/bin/env bash
# fullscreen_test.sh MODULE IMGCOMPARE [FIXED_RAND]: r_fullscreen 1 with a size the display lacks, as stock.
# Under a 1024x768 Xvfb screen, r_mode -1 640x360 r_fullscreen 1: stock opengl1's screenshot is the
# 640x360 picture (drawn from the bottom-left of the 1024x768 surface). Ours must give the same
# size and the picture it gives in a 640x360 window, and resemble opengl1's at the same view.
# Stock runs fullscreen with a hardware gamma ramp and 1 overbright bit there (its log says
# "GAMMA: hardware w/ 1 overbright bits"); ours presents without overbright (engine_glue README,
# "Settings"), so the content check against opengl1 fullscreen is looser than against its window.
# FIXED_RAND (optional, tests/regress pa_fixed_rand.so) is preloaded into the engine so that the
# game's random effects repeat from run to run (tests/regress/README.md).
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/engine_env.sh"
module="$1"; imgcompare="$2"
[[ -n "${3:-}" ]] && export PA_ENGINE_PRELOAD="$3"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
out="$(mktemp -d /tmp/pa-fullscreen.XXXXXX)"
trap 'rm -rf "$out"' EXIT
view="150 -674 -250 0"   # oa_dm7, facing a lit wall (tests/fidelity/README.md views)
capture() {   # capture NAME RENDERER FULLSCREEN
  local name="$1" renderer="$2" fullscreen="$3" screen=""
  [[ "$fullscreen" == 1 ]] && screen=1024x768x24
  PA_XVFB_SCREEN="$screen" "$here/capture_view.sh" "$out/$name" "$renderer" "$module" oa_dm7 "$view" -- \
    +set r_fullscreen "$fullscreen" +set r_pt_preset lightmap +set r_pt_scale 1 >"$out/$name.out" 2>&1 ||
    { cat "$out/$name.out"; tail -n 40 "$out/$name/engine.log" 2>/dev/null; echo "FAIL: capture $name"; exit 1; }
  [[ -f "$out/$name/view_1.tga" ]] || { echo "FAIL: $name wrote no screenshot"; exit 1; }
}
size() { python3 -c 'import struct,sys; d=open(sys.argv[1],"rb").read(18); print("%dx%d" % struct.unpack("<HH", d[12:16]))' "$1"; }
capture stock_full opengl1 1
capture ours_full pathtracer 1
capture ours_window pathtracer 0
capture stock_window opengl1 0
status=0
for name in stock_full ours_full ours_window stock_window; do
  got="$(size "$out/$name/view_1.tga")"
  echo "$name: $got"
  [[ "$got" == 640x360 ]] || { echo "FAIL: $name screenshot is $got, not 640x360"; status=1; }
done
grep -q "MODE: -1, 640 x 360 fullscreen" "$out/stock_full/engine.log" || { echo "FAIL: opengl1 did not run fullscreen"; status=1; }
compare() {   # compare A B MIN_PSNR MIN_SSIM
  echo "$1 vs $2: $("$imgcompare" "$out/$1/view_1.tga" "$out/$2/view_1.tga")"
  "$imgcompare" "$out/$1/view_1.tga" "$out/$2/view_1.tga" --min-psnr "$3" --min-ssim "$4" >/dev/null ||
    { echo "FAIL: $1 vs $2 below PSNR $3 dB / SSIM $4"; status=1; }
}
# Thresholds: this view measured 26.1-28.5 dB / 0.64-0.77 against stock's window and 21.3-21.8 dB /
# 0.56-0.61 against stock fullscreen (2-core machine, 2026-12-02; shader animation and the
# screenshot's game time move the veins); the broken fullscreen picture (1024x768, mostly black)
# fails the size check.
compare ours_full ours_window 26 0.70      # the same picture as in a window of that size (the
                                           # animated veins differ with the screenshot's game
                                           # time: 29.9 dB / 0.79 measured; a shifted or cropped
                                           # picture scores far lower)
compare ours_full stock_window 24 0.55     # the stock look without hardware overbright
compare ours_full stock_full 19 0.45       # stock fullscreen (brighter: 1 overbright bit)
exit $status
