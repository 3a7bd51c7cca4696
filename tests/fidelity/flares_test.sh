#!/usr/bin/env bash
# flares_test.sh MODULE IMGCOMPARE: r_flares 1 on an installed map against stock opengl1. oa_dm1,
# view "350 1300 184 0" (two torch flares, `textures/sfx/flameflare`, on the wall ahead): our
# module with flares must match opengl1 with flares much better than our module without them.
# Thresholds: tests/fidelity/README.md, "Flares". Exit 77 when the engine, the game data or
# xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/engine_env.sh"
module="$1"; imgcompare="$2"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
out="$(mktemp -d /tmp/pa-flares.XXXXXX)"
trap 'rm -rf "$out"' EXIT
capture() {   # capture NAME RENDERER FLARES
  # pmove_fixed 1: the noclip drift after setviewpos ends at the same place at any frame rate.
  "$here/capture_view.sh" "$out/$1" "$2" "$module" oa_dm1 "350 1300 184 0" -- +set pmove_fixed 1 \
    +set r_flares "$3" +set r_pt_preset lightmap +set r_pt_scale 1 >"$out/$1.out" 2>&1 ||
    { cat "$out/$1.out"; tail -n 40 "$out/$1/engine.log" 2>/dev/null; echo "FAIL: capture $1"; exit 1; }
}
capture stock opengl1 1
capture ours pathtracer 1
capture ours_off pathtracer 0
status=0
on="$("$imgcompare" "$out/ours/view_1.tga" "$out/stock/view_1.tga")"
off="$("$imgcompare" "$out/ours_off/view_1.tga" "$out/stock/view_1.tga")"
echo "flares on, ours vs opengl1: $on"
echo "ours without flares vs opengl1 with: $off"
"$imgcompare" "$out/ours/view_1.tga" "$out/stock/view_1.tga" --min-psnr 34 --min-ssim 0.94 >/dev/null ||
  { echo "FAIL: flares on below 34 dB / SSIM 0.94"; status=1; }
# Without flares the picture must be clearly worse (measured 24.4 dB): the flares are drawn.
awk -v f="$off" 'BEGIN { split(f, kv, " "); split(kv[1], p, "="); exit !(p[2] < 30) }' ||
  { echo "FAIL: ours without flares is as close to opengl1 with flares as with them"; status=1; }
exit $status
