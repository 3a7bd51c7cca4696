#!/usr/bin/env bash
# fidelity_test.sh MODULE PA_IMGCOMPARE [OUT_DIR]
# The lightmap preset against the stock opengl1 renderer of the same engine: both play
# demo088-test1 as a timedemo at 640x360 and capture the same engine frames (capture_frames.sh);
# every pair is compared with pa-imgcompare (PSNR over RGB, SSIM on luma) and must reach
#   FIDELITY_MIN_PSNR (dB) and FIDELITY_MIN_SSIM, defaults below, measured on Debian 12's
#   ioquake3 1.36+u20221123 + Mesa llvmpipe (see README.md for the figures and the margin).
# OUT_DIR (default: a temporary folder, removed) keeps the frames, diff images and results.tsv.
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
module="$1"; compare="$2"; out="${3:-}"
frames="${FIDELITY_FRAMES:-40 80 120 160 200}"
# The glue's screenshot command reads back the frame finished before the command, as stock
# opengl1 does, so the same wait-tick is the same moment (README.md: before that fix the stock
# frame at tick N+2 matched ours at N; FIDELITY_STOCK_TICK_OFFSET kept for such comparisons).
stock_offset="${FIDELITY_STOCK_TICK_OFFSET:-0}"
stock_frames="$(for f in $frames; do printf '%d ' $((f + stock_offset)); done)"
min_psnr="${FIDELITY_MIN_PSNR:-23.0}"
min_ssim="${FIDELITY_MIN_SSIM:-0.80}"
if [[ -z "$out" ]]; then out="$(mktemp -d /tmp/pa-fidelity.XXXXXX)"; trap 'rm -rf "$out"' EXIT; fi
mkdir -p "$out"
# Same cvars for both: no console notify lines (the screenshot messages differ), no FPS counter.
common=(+set con_notifytime -1 +set cg_drawFPS 0)
status=0
"$here/capture_frames.sh" "$out/opengl1" opengl1 none "$stock_frames" "${common[@]}" || status=$?
[[ $status -eq 77 ]] && exit 77
[[ $status -eq 0 ]] || { echo "FAIL: opengl1 capture"; exit 1; }
"$here/capture_frames.sh" "$out/lightmap" pathtracer "$module" "$frames" "${common[@]}" \
  +set r_pt_preset lightmap +set r_pt_scale 1 || { echo "FAIL: pathtracer capture"; exit 1; }

printf 'frame\tpsnr_db\tssim\n' >"$out/results.tsv"
failed=0
for frame in $frames; do
  name="$(printf 'frame_%04d' "$frame")"
  stock_name="$(printf 'frame_%04d' $((frame + stock_offset)))"
  set +e
  line="$("$compare" "$out/opengl1/$stock_name.tga" "$out/lightmap/$name.tga" --diff "$out/diff_$name.png" \
          --min-psnr "$min_psnr" --min-ssim "$min_ssim")"
  rc=$?
  set -e
  [[ $rc -le 1 ]] || { echo "FAIL: cannot compare $name"; exit 1; }
  psnr="$(sed -n 's/.*psnr_db=\([^ ]*\).*/\1/p' <<<"$line")"
  ssim="$(sed -n 's/.*ssim=\([^ ]*\).*/\1/p' <<<"$line")"
  printf '%s\t%s\t%s\n' "$frame" "$psnr" "$ssim" >>"$out/results.tsv"
  echo "frame $frame: $line$([[ $rc -eq 1 ]] && echo '  BELOW THRESHOLD')"
  [[ $rc -eq 0 ]] || failed=1
done
awk -F'\t' 'NR>1 {p+=$2; s+=$3; n++} END {if (n) printf "mean over %d frames: psnr_db=%.3f ssim=%.5f\n", n, p/n, s/n}' "$out/results.tsv"
echo "thresholds: psnr_db >= $min_psnr, ssim >= $min_ssim"
[[ $failed -eq 0 ]] && echo "PASS" || { echo "FAIL: a frame is below the thresholds"; exit 1; }
