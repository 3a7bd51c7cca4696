#!/usr/bin/env bash
# scripts/quality_along_demos.sh OUT_DIR [options]: the error of play configurations against a
# converged reference of the same game state, frame by frame along demos, in the real engine.
#
# For each demo, one timedemo run per configuration captures FRAMES consecutive rendered frames
# from command-buffer tick START (two ticks per rendered frame); one more run renders the same
# frames as references: the `path` preset with REF_SPP samples per pixel in each frame at
# r_pt_scale REF_SCALE, without temporal history, denoiser, firefly spreading or ReSTIR. The
# reference settings are switched on 4 ticks before START, so the game before them plays at
# 1 spp. Both keep the preset's radiance clamp (r_pt_clamp). Every run writes the same screenshot
# names, so the console line that reports them is the same in every image. timedemo makes tick N the same game moment in every run (tests/fidelity/capture_frames.sh)
# and pa_fixed_rand.so (tests/regress) the same random effects.
#
# Per frame: PSNR, SSIM, the mean-luminance ratio (configuration / reference) and, where
# pa-imgcompare prints it, FLIP, of each configuration's screenshot against the reference; per
# demo and configuration, their means. Writes OUT_DIR/frames.tsv, OUT_DIR/summary.tsv and the
# screenshots (OUT_DIR/DEMO/CONFIG/). Game images stay out of the repository: OUT_DIR is yours.
#
# Options:
#   --demos "a b ..."      names in tests/demos (without .dm_71) or OpenArena's demo088-test1
#                          (default: dm3_rockets czest1dm_ffa sago2_ctf)
#   --frames N             consecutive frames per demo (default 20)
#   --start TICK           first captured tick (default 200, even)
#   --ref-spp N            samples per pixel of each reference frame (default 1024, at most 4096)
#   --ref-scale S          r_pt_scale of the references (default 1: the window's resolution)
#   --config "NAME=ARGS"   a configuration: a name and its engine arguments (repeatable; default
#                          one, path="+set r_pt_preset path")
#   --module PATH          our module (default build/port/engine_glue/renderer_pathtracer_x86_64.so)
# Cost: a reference frame takes REF_SPP x (REF_SCALE^2 x 640 x 360) samples; on 2 cores about
# 0.4 s per sample per pixel at 640x360 for `path`, so the defaults take hours per demo: lower
# --ref-spp to try it out, and say so beside the figures.
# Needs ioquake3, openarena and xvfb-run (scripts/setup.sh) and a built tree (pa-imgcompare,
# pa_fixed_rand.so). Exit 77 when the engine or the game data is missing.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tests/fidelity/engine_env.sh"
out="${1:?usage: quality_along_demos.sh OUT_DIR [--demos ...] [--frames N] [--start T] [--ref-spp N] [--ref-scale S] [--config NAME=ARGS] [--module PATH]}"
shift
demos="dm3_rockets czest1dm_ffa sago2_ctf"
frames=20; start=200; ref_spp=1024; ref_scale=1
module="$root/build/port/engine_glue/renderer_pathtracer_x86_64.so"
config_names=(); config_args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --demos) demos="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --start) start="$2"; shift 2 ;;
    --ref-spp) ref_spp="$2"; shift 2 ;;
    --ref-scale) ref_scale="$2"; shift 2 ;;
    --config)
      [[ "$2" == *=* && "${2%%=*}" =~ ^[A-Za-z0-9_.+-]+$ ]] || { echo "quality_along_demos: --config NAME=ARGS, got '$2'" >&2; exit 2; }
      config_names+=("${2%%=*}"); config_args+=("${2#*=}"); shift 2 ;;
    --module) module="$2"; shift 2 ;;
    *) echo "quality_along_demos: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ "$frames" =~ ^[1-9][0-9]*$ && "$start" =~ ^[0-9]+$ && $((start % 2)) -eq 0 && "$start" -ge 6 ]] ||
  { echo "quality_along_demos: --frames must be positive and --start even and at least 6" >&2; exit 2; }
[[ "$ref_spp" =~ ^[1-9][0-9]*$ && "$ref_spp" -le 4096 ]] || { echo "quality_along_demos: --ref-spp in 1..4096" >&2; exit 2; }
[[ "$ref_scale" =~ ^(0?\.[0-9]+|1(\.0*)?)$ ]] || { echo "quality_along_demos: --ref-scale in (0, 1]" >&2; exit 2; }
if [[ ${#config_names[@]} -eq 0 ]]; then config_names=(path); config_args=("+set r_pt_preset path"); fi
pa_engine_available || { echo "quality_along_demos: needs ioquake3, openarena and xvfb-run (scripts/setup.sh)"; exit 77; }
compare="$root/build/tests/fidelity/pa-imgcompare"
fixed_rand="$root/build/tests/regress/pa_fixed_rand.so"
[[ -x "$compare" && -f "$fixed_rand" && -f "$module" ]] || { echo "quality_along_demos: build the tree first (pa-imgcompare, pa_fixed_rand.so, the module)" >&2; exit 2; }
export PA_ENGINE_PRELOAD="$fixed_rand" PA_FIXED_RAND_SEED=1
mkdir -p "$out"
ticks=""
for ((i = 0; i < frames; ++i)); do ticks+="$((start + 2 * i)) "; done
ticks="${ticks% }"
# Long runs: the references take REF_SPP samples per pixel per frame.
seconds=$((600 + frames * ref_spp * 2))
common=(+set sv_pure 0 +set r_pt_stats 0)

demo_path() {   # a tests/demos name -> its file; OpenArena's own demos by name
  if [[ -f "$root/tests/demos/$1.dm_71" ]]; then echo "$root/tests/demos/$1.dm_71"; else echo "$1"; fi
}

# The reference run: a capture cfg whose first wait ends 4 ticks before START with the
# reference settings.
capture_reference() {   # DEMO OUT_DIR
  local demo="$1" dir="$2" work status=0 tick previous
  work="$(mktemp -d /tmp/pa-quality.XXXXXX)"
  pa_engine_prepare "$work" "$module"
  local demo_name="$demo"
  if [[ "$demo" == *.dm_71 ]]; then
    mkdir -p "$work/home/baseoa/demos"
    cp "$demo" "$work/home/baseoa/demos/pa_capture.dm_71"
    demo_name=pa_capture
  fi
  local cfg
  cfg="$(pa_engine_cfg "$work" capture)"
  {
    printf 'wait %d\n' $((start - 4))
    printf 'set r_pt_preset path\nset r_pt_spp %d\nset r_pt_scale %s\nset r_pt_temporal 0\n' "$ref_spp" "$ref_scale"
    printf 'set r_pt_denoise 0\nset r_pt_fireflies 0\nset r_pt_restir 0\n'
    previous=$((start - 4))
    for tick in $ticks; do
      printf 'wait %d\nscreenshot frame_%04d\n' $((tick - previous)) "$tick"
      previous=$tick
    done
    printf 'wait 5\nquit\n'
  } >"$cfg"
  mkdir -p "$dir"
  pa_engine_run "$work" "$dir/engine.log" "$seconds" 640 360 pathtracer \
    +set timedemo 1 +set com_maxfps 0 +set cg_drawFPS 0 "${common[@]}" +set r_pt_preset path \
    +demo "$demo_name" +exec capture.cfg || status=$?
  cp "$work"/home/baseoa/screenshots/frame_*.tga "$dir/" 2>/dev/null || true
  rm -rf "$work"
  [[ $status -eq 0 ]] || { echo "reference run of $demo failed with status $status (log: $dir/engine.log)"; return 1; }
  for tick in $ticks; do
    [[ -f "$dir/$(printf 'frame_%04d.tga' "$tick")" ]] || { echo "reference tick $tick missing (log: $dir/engine.log)"; return 1; }
  done
}

frames_tsv="$out/frames.tsv"
printf 'demo\tconfig\ttick\tpsnr_db\tssim\tluma_ratio\tflip\n' >"$frames_tsv"
for demo in $demos; do
  file="$(demo_path "$demo")"
  echo "== $demo: reference frames ($ref_spp spp at r_pt_scale $ref_scale, ticks $start..$((start + 2 * (frames - 1))))"
  capture_reference "$file" "$out/$demo/reference"
  for c in "${!config_names[@]}"; do
    name="${config_names[$c]}"
    read -r -a args <<<"${config_args[$c]}"
    echo "== $demo: $name (${config_args[$c]})"
    pa_capture_demo_ticks "$out/$demo/$name" pathtracer "$module" "$file" frame "$ticks" "$seconds" \
      "${common[@]}" "${args[@]}"
    for tick in $ticks; do
      line="$("$compare" "$out/$demo/reference/$(printf 'frame_%04d.tga' "$tick")" \
        "$out/$demo/$name/$(printf 'frame_%04d.tga' "$tick")" --json || true)"
      python3 - "$demo" "$name" "$tick" "$line" >>"$frames_tsv" <<'PY'
import json, sys
demo, name, tick, line = sys.argv[1:5]
m = json.loads(line)
flip = m.get("flip", m.get("flip_mean"))
print("\t".join([demo, name, tick, f"{m['psnr_db']:.2f}", f"{m['ssim']:.4f}", f"{m['luma_ratio']:.3f}",
                 "" if flip is None else f"{flip:.4f}"]))
PY
    done
  done
done
python3 - "$frames_tsv" "$out/summary.tsv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
groups = {}
for r in rows:
    groups.setdefault((r["demo"], r["config"]), []).append(r)
with open(sys.argv[2], "w") as f:
    f.write("demo\tconfig\tframes\tmean_psnr_db\tmean_ssim\tmean_luma_ratio\tmin_luma_ratio\tmean_flip\n")
    for (demo, config), rs in groups.items():
        mean = lambda k: statistics.fmean(float(r[k]) for r in rs)
        flips = [float(r["flip"]) for r in rs if r["flip"]]
        f.write(f"{demo}\t{config}\t{len(rs)}\t{mean('psnr_db'):.2f}\t{mean('ssim'):.4f}\t{mean('luma_ratio'):.3f}\t"
                f"{min(float(r['luma_ratio']) for r in rs):.3f}\t{statistics.fmean(flips) if flips else float('nan'):.4f}\n")
PY
column -t -s $'\t' "$out/summary.tsv"
