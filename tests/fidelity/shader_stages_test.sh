#!/usr/bin/env bash
# shader_stages_test.sh MODULE IMGCOMPARE [OUT]: surfaces whose look comes from several shader
# stages, in real OpenArena maps, with our module (lightmap preset) and with stock opengl1,
# compared (thresholds: tests/fidelity/README.md, "Cover stages"): floors that blend an image over
# their base before the lightmap (MaterialDesc::coverTexture: launch and jump pads' frames over
# scrolling or blinking effects; without it our pads showed their effect texture where stock
# shows the pad), seen straight down; a teleporter whose rings are a clampMap glow stage of an
# additive surface light; terrain blended by vertex alpha under a lightmap stage that doubles
# (GL_DST_COLOR GL_SRC_COLOR); an energy field that multiplies what is behind it (blendFunc
# filter); painted metal with holes over chrome; trims that add their texture over chrome before
# the lightmap. OUT (optional) keeps the screenshots.
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/engine_env.sh"
module="$1"; imgcompare="$2"; keep="${3:-}"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
out="$(mktemp -d /tmp/pa-shader-stages.XXXXXX)"
trap 'rm -rf "$out"' EXIT
status=0
# name map view look (down: straight down, else ahead) crop (x,y,w,h; "-": the whole picture)
# min_psnr min_ssim. The effects animate (blinking arrows, scrolling treads, pulsing rings):
# `fixedtime 50` makes every frame 50 ms of game time, so both renderers draw them at the same
# shader time.
cases=(
  "jumppad wrackdm17 1216_-192_380_90 down - 40 0.97"                  # textures/cosmo_sfx/dm17_jpad
  "launchpad oa_ctf4ish 188_-320_1170_90 down - 35 0.97"               # textures/sfx2/blue_launchpad
  "e8pad oa_thor 3344_0_40_90 down 262,0,120,290 35 0.97"              # textures/bubctf1/e8_launchpad1, two pads
  "rings oa_ctf4ish -8_-256_1156_-18 ahead 420,110,130,140 24 0.94"    # textures/ctf/blue_telep2
  "terrain islandctf -864_0_532_-27 ahead - 33 0.95"                   # textures/islandctf/terrain_*
  "energy ctf_gate1 624_160_-14_270 ahead - 33 0.96"                   # textures/cosmo_sfx/energy_red (filter)
  "chrome hydronex -584_1848_74_180 ahead - 25 0.93"                   # textures/evil8_base/e8metal_red_shiney
  "trims sleekgrinder 40_128_-14_0 ahead - 34 0.97"                    # textures/base_trim/tin (added, then lit)
)
for c in "${cases[@]}"; do
  read -r name map view look crop psnr ssim <<<"$c"
  view="${view//_/ }"
  down=""
  [[ "$look" == down ]] && down=1
  for renderer in opengl1 pathtracer; do
    CAPTURE_LOOK_DOWN="$down" "$here/capture_view.sh" "$out/$name.$renderer" "$renderer" "$module" "$map" "$view" -- \
      +set fixedtime 50 +set r_pt_preset lightmap +set r_pt_scale 1 >"$out/$name.$renderer.out" 2>&1 ||
      { cat "$out/$name.$renderer.out"; echo "FAIL: capture $name with $renderer"; status=1; }
  done
done
[[ -n "$keep" ]] && { mkdir -p "$keep"; cp -r "$out"/. "$keep/"; }
[[ $status -eq 0 ]] || exit 1
for c in "${cases[@]}"; do
  read -r name map view look crop psnr ssim <<<"$c"
  a="$out/$name.pathtracer/view_1.tga" b="$out/$name.opengl1/view_1.tga"
  args=()
  [[ "$crop" != - ]] && args=(--crop "$crop")
  echo "$name ($map, crop $crop): ours vs opengl1: $("$imgcompare" "$a" "$b" "${args[@]}")"
  "$imgcompare" "$a" "$b" "${args[@]}" --min-psnr "$psnr" --min-ssim "$ssim" >/dev/null ||
    { echo "FAIL: $name below PSNR $psnr dB / SSIM $ssim"; status=1; }
done
exit $status
