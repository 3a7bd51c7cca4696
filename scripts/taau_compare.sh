#!/usr/bin/env bash
# scripts/taau_compare.sh OUT_DIR [MODULE]: the lightmap preset at r_pt_scale 0.5 with TAAU
# (r_pt_taau 1) and with the bilinear stretch (r_pt_taau 0), and at r_pt_scale 1, against
# opengl1 and against the scale-1 picture, on two views of each of oa_dm1, oa_dm3, oa_rpg3dm2
# and wrackdm17 (the contact-sheet views; tests/fidelity/capture_view.sh: devmap, noclip,
# setviewpos, 40 still frames, screenshot; 640x360). Prints one line per view and configuration
# with pa-imgcompare's PSNR and SSIM, and keeps the screenshots in OUT_DIR (game images: keep
# them out of the repository). Needs ioquake3, openarena and xvfb-run (scripts/setup.sh).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:?usage: taau_compare.sh OUT_DIR [MODULE]}"
module="${2:-$here/build/port/engine_glue/renderer_pathtracer_x86_64.so}"
compare="$here/build/tests/fidelity/pa-imgcompare"
[[ -x "$compare" ]] || { echo "taau_compare: build pa-imgcompare first" >&2; exit 1; }
declare -A views=(
  [oa_dm1]="280.0 1416.0 -94.0 180.0|-656.0 976.0 50.0 90.0"
  [oa_dm3]="512.0 896.0 66.0 270.0|192.0 -208.0 -150.0 90.0"
  [oa_rpg3dm2]="-480.0 208.0 178.0 45.0|-192.0 1728.0 306.0 315.0"
  [wrackdm17]="-768.0 -448.0 322.0 180.0|-864.0 -32.0 82.0 -0.0"
)
maps="oa_dm1 oa_dm3 oa_rpg3dm2 wrackdm17"
capture() {   # capture CONFIG RENDERER [engine args]
  local config="$1" renderer="$2"; shift 2
  for map in $maps; do
    IFS='|' read -r a b <<<"${views[$map]}"
    "$here/tests/fidelity/capture_view.sh" "$out/$config/$map" "$renderer" "$module" "$map" "$a" "$b" -- "$@" \
      >/dev/null || { echo "taau_compare: capture of $map ($config) failed" >&2; exit 1; }
  done
}
capture opengl1 opengl1
capture full pathtracer +set r_pt_preset lightmap +set r_pt_scale 1 +set r_pt_taau 0
capture bilinear pathtracer +set r_pt_preset lightmap +set r_pt_scale 0.5 +set r_pt_taau 0
capture taau pathtracer +set r_pt_preset lightmap +set r_pt_scale 0.5 +set r_pt_taau 1
metric() { "$compare" "$1" "$2" | awk '{print $1, $2}'; }
for config in bilinear taau full; do
  for map in $maps; do
    for v in 1 2; do
      shot="$out/$config/$map/view_$v.tga"
      echo "$config $map view_$v vs_opengl1 $(metric "$out/opengl1/$map/view_$v.tga" "$shot") vs_scale1 $(metric "$out/full/$map/view_$v.tga" "$shot")"
    done
  done
done
