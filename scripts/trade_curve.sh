#!/usr/bin/env bash
# trade_curve.sh SCENE OUT_DIR CAMERA [CAMERA ...]
# Error against time per frame for every preset and knob, offline with pa-render on a map: MAP.bsp
# (read from the installed game, with its bake, as the game draws it) or a converted map
# (build/assets_converter/assets_converter --game /usr/share/games/openarena/baseoa --map MAP -o DIR;
# glTF holds no bake, so --baked-path-end changes nothing there).
# Per camera: a converged reference (path, REF_BOUNCES bounces, no clamp, REF_SPP x REF_FRAMES spp
# accumulated), then each configuration below at WIDTH x WIDTH*9/16 (the traced size; scaled
# configurations are traced smaller and stretched bilinearly to it, as the game stretches), every
# image in the game's default look (r_pt_look stock: --tonemap clamp --lighting display).
# Played configurations render FRAMES frames of the still view (the last one compared).
# Writes OUT_DIR/trade.tsv (scene, camera, group, config, ms per frame: the steady cost,
# (render_seconds - first_frame_seconds) / (frames - 1); mean FLIP, PSNR, SSIM, luma ratio
# against the reference) and, when gnuplot is installed,
# OUT_DIR/trade_cCAM.png: FLIP and PSNR against ms per frame, one point per configuration.
# Environment: WIDTH (320), FRAMES (8), REF_SPP (64), REF_FRAMES (16), REF_BOUNCES (4),
# THREADS (0 = all cores), PPD (FLIP's pixels per degree, default the paper's 67.02),
# PLOT_ONLY (1: plot OUT_DIR/trade.tsv again without rendering), ONLY (an awk regular expression:
# only the configurations whose names match, e.g. "^(direct|path)$"; the reference is always made).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
render="${PA_RENDER:-$here/build/renderer/cli/pa-render}"
compare="${PA_IMGCOMPARE:-$here/build/tests/fidelity/pa-imgcompare}"
[[ $# -ge 3 ]] || { echo "usage: $0 SCENE OUT_DIR CAMERA [CAMERA ...]" >&2; exit 2; }
scene="$1"; out="$2"; shift 2
width="${WIDTH:-320}"; height=$(( width * 9 / 16 )); frames="${FRAMES:-8}"; threads="${THREADS:-0}"
ppd_args=(); [[ -n "${PPD:-}" ]] && ppd_args=(--ppd "$PPD")
command -v convert >/dev/null || { echo "needs ImageMagick's convert (scripts/setup.sh)" >&2; exit 2; }
mkdir -p "$out"
look=(--tonemap clamp --lighting display)
name="$(basename "$(basename "$scene" .glb)" .bsp)"
tsv="$out/trade.tsv"
[[ -f "$tsv" ]] || printf 'scene\tcamera\tgroup\tconfig\tms_per_frame\tflip\tpsnr_db\tssim\tluma_ratio\n' >"$tsv"

# The game's presets (port/engine_glue: r_pt_spp 1, r_pt_bounces 2, clamp 10, temporal,
# denoiser and firefly spreading on, paths ending on the bake (r_pt_bake_end 1), Russian roulette
# from the first bounce (r_pt_roulette 1); `reference` accumulates without clamp), then one knob at a
# time around `path`. Columns: group, config, scale, extra pa-render arguments (a repeated option:
# the last one counts, so the roulette rows' --roulette-start 3 overrides $play's 1).
configs() {
  local play="--play temporal --denoise --spread-fireflies --frames $frames --roulette-start 1"
  cat <<EOF
preset lightmap 1 --integrator lightmap --spp 1 --play independent --frames 4
preset direct 1 --integrator direct --clamp 10 --spp 1 $play --baked-path-end
preset path 1 --integrator path --bounces 2 --clamp 10 --spp 1 $play --baked-path-end
preset reference_4f 1 --integrator path --bounces 2 --clamp 0 --spp 1 --frames 4 --baked-path-end --roulette-start 1
preset reference_16f 1 --integrator path --bounces 2 --clamp 0 --spp 1 --frames 16 --baked-path-end --roulette-start 1
preset reference_64f 1 --integrator path --bounces 2 --clamp 0 --spp 1 --frames 64 --baked-path-end --roulette-start 1
spp path_spp2 1 --integrator path --bounces 2 --clamp 10 --spp 2 $play --baked-path-end
spp path_spp4 1 --integrator path --bounces 2 --clamp 10 --spp 4 $play --baked-path-end
bounces path_bounces1 1 --integrator path --bounces 1 --clamp 10 --spp 1 $play --baked-path-end
bounces path_bounces4 1 --integrator path --bounces 4 --clamp 10 --spp 1 $play --baked-path-end
scale path_scale0.75 0.75 --integrator path --bounces 2 --clamp 10 --spp 1 $play --baked-path-end
scale path_scale0.5 0.5 --integrator path --bounces 2 --clamp 10 --spp 1 $play --baked-path-end
denoiser path_no_denoiser 1 --integrator path --bounces 2 --clamp 10 --spp 1 --play temporal --spread-fireflies --frames $frames --baked-path-end --roulette-start 1
temporal path_no_temporal 1 --integrator path --bounces 2 --clamp 10 --spp 1 --play independent --denoise --spread-fireflies --frames $frames --baked-path-end --roulette-start 1
temporal path_raw 1 --integrator path --bounces 2 --clamp 10 --spp 1 --play independent --frames $frames --baked-path-end --roulette-start 1
restir path_restir 1 --integrator path --bounces 2 --clamp 10 --spp 1 --restir $play --baked-path-end
restir direct_restir 1 --integrator direct --clamp 10 --spp 1 --restir $play --baked-path-end
clamp path_no_clamp 1 --integrator path --bounces 2 --clamp 0 --spp 1 $play --baked-path-end
bake path_no_bake 1 --integrator path --bounces 2 --clamp 10 --spp 1 $play
bake direct_no_bake 1 --integrator direct --clamp 10 --spp 1 $play
roulette direct_roulette3 1 --integrator direct --clamp 10 --spp 1 $play --baked-path-end --roulette-start 3
roulette path_roulette3 1 --integrator path --bounces 2 --clamp 10 --spp 1 $play --baked-path-end --roulette-start 3
roulette path_roulette3_spp2 1 --integrator path --bounces 2 --clamp 10 --spp 2 $play --baked-path-end --roulette-start 3
lampvis direct_no_lamp_vis 1 --integrator direct --clamp 10 --spp 1 $play --baked-path-end --no-lamp-visibility
lampvis path_no_lamp_vis 1 --integrator path --bounces 2 --clamp 10 --spp 1 $play --baked-path-end --no-lamp-visibility
EOF
}

for cam in "$@"; do
  [[ -n "${PLOT_ONLY:-}" ]] && break
  ref="$out/${name}_c${cam}_ref.png"
  if [[ ! -f "$ref" ]]; then
    "$render" "$scene" --camera "$cam" --width "$width" --height "$height" -q --threads "$threads" "${look[@]}" \
      --integrator path --bounces "${REF_BOUNCES:-4}" --clamp 0 --spp "${REF_SPP:-64}" --frames "${REF_FRAMES:-16}" \
      -o "$ref" --stats "$out/${name}_c${cam}_ref.json" 2>>"$out/render.log"
  fi
  while read -r group config scale args; do
    png="$out/${name}_c${cam}_$config.png"; stats="$out/${name}_c${cam}_$config.json"
    w=$(python3 -c "print(max(8, round($width * $scale)))"); h=$(python3 -c "print(max(8, round($height * $scale)))")
    # shellcheck disable=SC2086
    "$render" "$scene" --camera "$cam" --width "$w" --height "$h" -q --threads "$threads" "${look[@]}" $args \
      -o "$png" --stats "$stats" 2>>"$out/render.log"
    shown="$png"
    if [[ "$w" != "$width" ]]; then   # the game's bilinear stretch to the window
      shown="$out/${name}_c${cam}_${config}_shown.png"
      convert "$png" -filter Triangle -resize "${width}x${height}!" "$shown"
    fi
    # Steady cost: the first frame also builds what later frames reuse (about a second).
    ms=$(python3 -c "import json,sys; d=json.load(open(sys.argv[1])); f=d['frames']; t=d['render_seconds']
print('%.1f' % (1000*(t-d['first_frame_seconds'])/(f-1) if f > 1 else 1000*t))" "$stats")
    cmp=$("$compare" "$ref" "$shown" --json "${ppd_args[@]}" |
      python3 -c "import json,sys; d=json.load(sys.stdin); print('%.4f\t%.2f\t%.3f\t%.3f' % (d['flip'], d['psnr_db'], d['ssim'], d['luma_ratio']))")
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$cam" "$group" "$config" "$ms" "$cmp" | tee -a "$tsv"
  done < <(configs | awk -v only="${ONLY:-.}" '$2 ~ only')
done

command -v gnuplot >/dev/null || { echo "gnuplot not installed: table only ($tsv)"; exit 0; }
groups="preset spp bounces scale denoiser temporal restir clamp bake roulette lampvis"
for cam in "$@"; do
  rows="$out/${name}_c${cam}.dat"
  awk -F'\t' -v s="$name" -v c="$cam" 'NR > 1 && $1 == s && $2 == c { print $5, $6, $7, $4, $3 }' "$tsv" >"$rows"
  gnuplot <<EOF
set terminal pngcairo size 1400,600 font ",9" noenhanced
set output "$out/trade_${name}_c${cam}.png"
set multiplot layout 1,2 title "$name camera $cam, ${width}x${height}: error against a converged reference (path, ${REF_BOUNCES:-4} bounces, $(( ${REF_SPP:-64} * ${REF_FRAMES:-16} )) spp) and steady time per frame"
set linetype 9 lc rgb "#8c564b"
set linetype 10 lc rgb "#7f7f7f"
set linetype 11 lc rgb "#17becf"
set logscale x
set xlabel "ms per frame"
set grid
set key top right
set ylabel "mean FLIP (lower is better)"
plot for [i=1:words("$groups")] "$rows" using 1:(strcol(5) eq word("$groups", i) ? \$2 : NaN) with points lt i pt 7 ps 1.2 title word("$groups", i), \
     "$rows" using 1:2:4 with labels left offset char 0.6,0 font ",7" notitle
set key bottom right
set ylabel "PSNR dB (higher is better)"
plot for [i=1:words("$groups")] "$rows" using 1:(strcol(5) eq word("$groups", i) ? \$3 : NaN) with points lt i pt 7 ps 1.2 title word("$groups", i), \
     "$rows" using 1:3:4 with labels left offset char 0.6,0 font ",7" notitle
unset multiplot
EOF
  echo "plot: $out/trade_${name}_c${cam}.png"
done
