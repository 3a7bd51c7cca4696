#!/usr/bin/env bash
# scripts/taau_motion_compare.sh OUT_DIR [NAME=MODULE ...]: TAAU against the bilinear stretch on
# moving demo frames. For each demo in DEMOS (default: demo088-test1, tests/demos dm3_rockets and
# wrackdm17_ffa) it captures the frames FRAMES (default 40 100 160 220 280 340 400; command-buffer
# ticks of a timedemo, tests/fidelity/capture_frames.sh, game seed fixed as fidelity_test.sh does)
# with the lightmap preset at r_pt_scale 1 ("full"), at 0.5 stretched bilinearly ("bilinear"),
# and at 0.5 with TAAU ("taau"), and prints pa-imgcompare's PSNR / SSIM of each against "full",
# per frame and as a mean per demo. With NAME=MODULE arguments, TAAU runs once per module (the
# first module also makes "full" and "bilinear"); without, the module in build/. Keeps the
# captures in OUT_DIR (game images: keep them out of the repository). Needs ioquake3, openarena
# and xvfb-run (scripts/setup.sh).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:?usage: taau_motion_compare.sh OUT_DIR [NAME=MODULE ...]}"
shift
modules=("$@")
[[ ${#modules[@]} -gt 0 ]] || modules=("taau=$here/build/port/engine_glue/renderer_pathtracer_x86_64.so")
compare="$here/build/tests/fidelity/pa-imgcompare"
[[ -x "$compare" ]] || { echo "taau_motion_compare: build pa-imgcompare first" >&2; exit 1; }
fixed_rand="$here/build/tests/regress/pa_fixed_rand.so"
[[ -f "$fixed_rand" ]] && export PA_ENGINE_PRELOAD="$fixed_rand" PA_FIXED_RAND_SEED=1
demos="${DEMOS:-demo088-test1 dm3_rockets wrackdm17_ffa}"
frames="${FRAMES:-40 100 160 220 280 340 400}"
common=(+set con_notifytime -1 +set cg_drawFPS 0 +set r_pt_preset lightmap)
capture() {   # capture DEMO DIR MODULE [engine args]
  local demo="$1" dir="$2" module="$3" source="$1"
  shift 3
  [[ "$demo" == demo088-test1 ]] || source="$here/tests/demos/$demo.dm_71"
  [[ -f "$dir/frame_$(printf '%04d' "${frames##* }").tga" ]] && return 0   # already there
  CAPTURE_DEMO="$source" "$here/tests/fidelity/capture_frames.sh" "$dir" pathtracer "$module" "$frames" \
    "${common[@]}" "$@" >/dev/null || { echo "taau_motion_compare: capture of $demo ($dir) failed" >&2; exit 1; }
}
first="${modules[0]#*=}"
for demo in $demos; do
  capture "$demo" "$out/$demo/full" "$first" +set r_pt_scale 1 +set r_pt_taau 0
  capture "$demo" "$out/$demo/bilinear" "$first" +set r_pt_scale 0.5 +set r_pt_taau 0
  for entry in "${modules[@]}"; do
    capture "$demo" "$out/$demo/${entry%%=*}" "${entry#*=}" +set r_pt_scale 0.5 +set r_pt_taau 1
  done
done
field() { tr ' ' '\n' <<<"$line" | sed -n "s/^$1=//p"; }
printf 'demo\tconfig\tframe\tpsnr_db\tssim\n' >"$out/results.tsv"
for demo in $demos; do
  for config in bilinear "${modules[@]%%=*}"; do
    for frame in $frames; do
      name="$(printf 'frame_%04d.tga' "$frame")"
      line="$("$compare" "$out/$demo/full/$name" "$out/$demo/$config/$name")"
      printf '%s\t%s\t%s\t%s\t%s\n' "$demo" "$config" "$frame" "$(field psnr_db)" "$(field ssim)" >>"$out/results.tsv"
    done
  done
done
awk -F'\t' 'NR > 1 { k = $1 " " $2; p[k] += $4; s[k] += $5; n[k]++; if (!(k in seen)) { seen[k] = 1; order[++m] = k } }
  END { for (i = 1; i <= m; ++i) { k = order[i]; printf "%s mean vs full: %.2f dB / %.3f\n", k, p[k] / n[k], s[k] / n[k] } }' \
  "$out/results.tsv"
