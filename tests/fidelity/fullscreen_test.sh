#!/usr/bin/env bash
# fullscreen_test.sh MODULE IMGCOMPARE [FIXED_RAND]: r_fullscreen 1 with a size the display lacks, as stock.
# Under a 1024x768 Xvfb screen, r_mode -1 640x360 r_fullscreen 1: stock opengl1's screenshot is the
# 640x360 picture (drawn from the bottom-left of the 1024x768 surface). Ours must give the same
# size, the same picture as in a 640x360 window but for brightness, and stock's look in each mode:
# stock runs fullscreen with 1 overbright bit ("GAMMA: hardware w/ 1 overbright bits"): it draws
# lit surfaces at half and its gamma ramp doubles the frame (its screenshot applies the ramp),
# so its fullscreen picture is brighter than its window's; ours doubles texture x baked light in
# display values (engine_glue README, "Settings as stock").
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
trap '[[ -n "${FULLSCREEN_KEEP:-}" ]] && cp -r "$out"/. "$FULLSCREEN_KEEP"/; rm -rf "$out"' EXIT
view="150 -674 -250 0"   # oa_dm7, facing a lit wall (tests/fidelity/README.md views)
capture() {   # capture NAME RENDERER FULLSCREEN
  local name="$1" renderer="$2" fullscreen="$3" screen=""
  [[ "$fullscreen" == 1 ]] && screen=1024x768x24
  PA_XVFB_SCREEN="$screen" "$here/capture_view.sh" "$out/$name" "$renderer" "$module" oa_dm7 "$view" -- +set pmove_fixed 1 \
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
# Thresholds just below the figures measured on this view (pmove_fixed 1; Intel Xeon 2 shared
# cores, llvmpipe, 2026-12-02): ours window vs stock window 35.26 dB / 0.957; ours fullscreen vs
# stock fullscreen 29.09 / 0.933 (without the overbright factor, 24.19 / 0.889); ours fullscreen
# vs ours window SSIM 0.925 (brightness differs by design). The broken fullscreen picture
# (1024x768, mostly black) fails the size check; a shifted or cropped one the SSIM checks.
compare ours_full ours_window 0 0.90       # the same picture, brighter
compare ours_window stock_window 34 0.94   # stock's window look (no overbright)
compare ours_full stock_full 28 0.92       # stock's fullscreen look (1 overbright bit)
# Brighter fullscreen as stock: luma ratio fullscreen / window (stock measured 1.42, ours 1.51).
ratio() { "$imgcompare" "$out/$1/view_1.tga" "$out/$2/view_1.tga" | sed -n 's/.*luma_ratio=\([0-9.]*\).*/\1/p'; }
stock_ratio="$(ratio stock_window stock_full)"; ours_ratio="$(ratio ours_window ours_full)"
echo "fullscreen / window luma: stock $stock_ratio, ours $ours_ratio"
awk -v s="$stock_ratio" -v o="$ours_ratio" 'BEGIN { exit !(s > 1.2 && o > 0.9 * s && o < 1.15 * s) }' ||
  { echo "FAIL: fullscreen brightening differs from stock's (or stock ran without overbright)"; status=1; }
exit $status
