#!/usr/bin/env bash
# restir_bench.sh SCENE OUT_DIR CAMERA [CAMERA ...]
# Error against time per frame of reservoir resampling (pa-render --restir) against plain light
# sampling on the views of a scene (a converted map: assets_converter ... -o DIR). For each
# camera: a plain-integrator reference (REF_SPP x REF_FRAMES spp, accumulated), then played
# frames (--play independent: seed + frame, no accumulation, the last of FRAMES frames written;
# --restir keeps its reservoirs' history across them) at 1 spp with and without --restir, and
# without it at PLAIN_SPP spp (the equal-time comparison), and the same with the game's temporal
# accumulation and denoiser (--play temporal --denoise). Prints one row per configuration:
# ms per frame (render_seconds / frames), of which resampling, then pa-imgcompare's PSNR, SSIM
# and mean-luma ratio against the reference. Environment: INTEGRATOR (direct), WIDTH (320),
# EXPOSURE (8), FRAMES (8), PLAIN_SPP (4), REF_SPP (64), REF_FRAMES (16), THREADS (0 = all).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
render="${PA_RENDER:-$here/build/renderer/cli/pa-render}"
compare="${PA_IMGCOMPARE:-$here/build/tests/fidelity/pa-imgcompare}"
scene="$1"; out="$2"; shift 2
integrator="${INTEGRATOR:-direct}"; width="${WIDTH:-320}"; exposure="${EXPOSURE:-8}"
frames="${FRAMES:-8}"; plainSpp="${PLAIN_SPP:-4}"; threads="${THREADS:-0}"
mkdir -p "$out"
common=(--width "$width" -q --integrator "$integrator" --exposure "$exposure" --threads "$threads")
field() { python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1" "$2"; }
printf '%-8s %-28s %9s %9s %8s %7s %6s\n' camera config ms/frame resample psnr_dB ssim luma
for cam in "$@"; do
  ref="$out/ref_${integrator}_c$cam.png"
  if [[ ! -f "$ref" ]]; then
    "$render" "$scene" --camera "$cam" "${common[@]}" --spp "${REF_SPP:-64}" --frames "${REF_FRAMES:-16}" \
      -o "$ref" --stats "$out/ref_${integrator}_c$cam.json"
  fi
  while read -r name args; do
    png="$out/c${cam}_$name.png"; stats="$out/c${cam}_$name.json"
    # shellcheck disable=SC2086
    "$render" "$scene" --camera "$cam" "${common[@]}" --frames "$frames" $args -o "$png" --stats "$stats"
    ms=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print('%.0f %.0f' % (1000*d['render_seconds']/d['frames'], 1000*d['resample_seconds']/d['frames']))" "$stats")
    cmp=$("$compare" "$ref" "$png" --json | python3 -c "import json,sys; d=json.load(sys.stdin); print('%.2f %.3f %.3f' % (d['psnr_db'], d['ssim'], d['luma_ratio']))")
    read -r total resample <<<"$ms"; read -r psnr ssim luma <<<"$cmp"
    printf '%-8s %-28s %9s %9s %8s %7s %6s\n' "$cam" "$name" "$total" "$resample" "$psnr" "$ssim" "$luma"
  done <<EOF
plain_1spp --play independent --spp 1
plain_${plainSpp}spp --play independent --spp $plainSpp
restir_1spp --play independent --spp 1 --restir
plain_1spp_temporal_denoise --play temporal --denoise --spp 1
plain_${plainSpp}spp_temporal_denoise --play temporal --denoise --spp $plainSpp
restir_1spp_temporal_denoise --play temporal --denoise --spp 1 --restir
EOF
done
