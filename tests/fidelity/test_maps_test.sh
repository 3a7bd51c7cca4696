#!/usr/bin/env bash
# test_maps_test.sh MODULE IMGCOMPARE MAKE_MAPS [OUT]: maps with external, 512x512 and out-of-range
# lightmaps (written by MAKE_MAPS, tests/fidelity/make_test_maps.cpp: no game data) load in the
# real engine with our module (lightmap preset) and with stock opengl1, at the same view, and the
# pictures are compared (thresholds: tests/fidelity/README.md, "Test maps").
# A map counts as loaded when cgame answered `viewpos` (it exists only in a level) and the log has
# no error drop; a module that falls back to the menu fails. OUT (optional) keeps the screenshots.
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/engine_env.sh"
module="$1"; imgcompare="$2"; make_maps="$3"; keep="${4:-}"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
out="$(mktemp -d /tmp/pa-test-maps.XXXXXX)"
trap 'rm -rf "$out"' EXIT
"$make_maps" "$out/game" >/dev/null
export CAPTURE_GAME_FILES="$out/game"
view="100 256 100 0"   # inside the room, facing the +X wall, floor and ceiling in view
status=0
capture() {   # capture NAME RENDERER MAP [engine args...]
  local name="$1" renderer="$2" map="$3"
  shift 3
  "$here/capture_view.sh" "$out/$name" "$renderer" "$module" "$map" "$view" -- \
    +set pmove_fixed 1 +set r_pt_preset lightmap +set r_pt_scale 1 "$@" >"$out/$name.out" 2>&1 ||
    { cat "$out/$name.out"; tail -n 40 "$out/$name/engine.log" 2>/dev/null; echo "FAIL: capture $name"; return 1; }
  if ! grep -Eq '^\(-?[0-9]+ -?[0-9]+ -?[0-9]+\) : ' "$out/$name/engine.log" ||
     grep -Eq '^(\^[0-9])?(ERROR|Com_Error|Couldn.t load)' "$out/$name/engine.log"; then
    grep -E 'ERROR|Error|WARNING' "$out/$name/engine.log" | head -n 20
    echo "FAIL: $name: $map did not load (no viewpos answer, or an error drop)"; return 1
  fi
}
compare() {   # compare NAME MIN_PSNR MIN_SSIM
  local a="$out/ours_$1/view_1.tga" b="$out/stock_$1/view_1.tga"
  echo "$1: ours vs opengl1: $("$imgcompare" "$a" "$b")"
  "$imgcompare" "$a" "$b" --min-psnr "$2" --min-ssim "$3" >/dev/null ||
    { echo "FAIL: $1 below PSNR $2 dB / SSIM $3"; status=1; }
}
for map in pa_ext pa_lm512 pa_oor; do
  capture "stock_$map" opengl1 "$map" || status=1
  capture "ours_$map" pathtracer "$map" || status=1
done
capture stock_pa_flare opengl1 pa_flare +set r_flares 1 || status=1
capture ours_pa_flare pathtracer pa_flare +set r_flares 1 || status=1
capture ours_pa_flare_off pathtracer pa_flare +set r_flares 0 || status=1
capture stock_pa_flare_off opengl1 pa_flare +set r_flares 0 || status=1
[[ -n "$keep" ]] && { mkdir -p "$keep"; cp -r "$out"/. "$keep/"; }
[[ $status -eq 0 ]] || exit 1
# Thresholds just below the figures measured (tests/fidelity/README.md, "Test maps").
compare pa_oor 35.5 0.965     # both vertex-lit
compare pa_ext 19.5 0.95      # stock vertex-lit, ours from lm_0000 (same gradient: a shape check)
compare pa_lm512 42 0.98      # both from the shader's image, unbrightened
# Flares (r_flares 1): the open flare projects to about (375, 180) and the one behind the screen
# to about (214, 195) from the view the pmove_fixed drift ends at (135 256 127).
crop() {   # crop NAME A B RECT MIN_PSNR MAX_PSNR MIN_SSIM
  local figures
  figures="$("$imgcompare" "$out/$2/view_1.tga" "$out/$3/view_1.tga" --crop "$4")"
  echo "$1 ($2 vs $3, $4): $figures"
  awk -v f="$figures" -v lo="$5" -v hi="$6" -v s="$7" 'BEGIN {
    split(f, kv, " "); for (i in kv) { split(kv[i], p, "="); v[p[1]] = p[2] }
    exit !(v["psnr_db"] >= lo && v["psnr_db"] <= hi && v["ssim"] >= s) }' ||
    { echo "FAIL: $1 outside PSNR [$5, $6] dB / SSIM >= $7"; status=1; }
}
flare=275,100,200,160; hidden=154,135,120,120
crop "flare as stock" ours_pa_flare stock_pa_flare "$flare" 44 999 0.995
crop "flare drawn" ours_pa_flare ours_pa_flare_off "$flare" 0 30 0
crop "hidden flare not drawn" ours_pa_flare ours_pa_flare_off "$hidden" 45 999 0.99
crop "hidden flare, stock" stock_pa_flare stock_pa_flare_off "$hidden" 45 999 0.99
exit $status
