#!/usr/bin/env bash
# demo_quality.sh OUT_DIR DEMO [DEMO ...]
# Quality along demos, in the real engine: for each demo (a name in tests/demos or a .dm_71 path)
# FRAMES consecutive rendered frames (ticks START, START+2, ...: two command-buffer
# ticks per frame, tests/fidelity/README.md) are captured under `timedemo 1` once per configuration,
# and a reference of the same ticks: preset `path` without history or filtering (r_pt_temporal 0,
# r_pt_denoise 0, r_pt_fireflies 0, r_pt_restir 0, r_pt_clamp 0, r_pt_scale 1, r_pt_bounces
# REF_BOUNCES) at r_pt_spp REF_SPP, REF_RUNS runs with r_pt_seed 1000, 2000, ..., their screenshots
# averaged (ImageMagick; a mean of display values, which equals the display of the mean radiance
# wherever no run clips). Timedemo sets the game clock from the frame count and every run preloads
# tests/regress's pa_fixed_rand.so (seed 1), so tick N is the same game state in every run: the
# demo cannot be frozen in timedemo (the clock ignores cl_freezeDemo), hence one frame per tick.
# Writes OUT_DIR/quality.tsv (demo, config, tick, FLIP, PSNR, luma ratio against the reference)
# and prints per demo and configuration the means and the engine's mean frame_ms (the r_pt_stats
# lines of the configuration's preset, every 2 s of its run).
# Environment: CONFIGS (default "path path:r_pt_temporal=0 path:r_pt_restir=1"; PRESET:cvar=v,...),
# FRAMES (20), START (200), WARMUP (16: the configuration starts that many ticks, 8 frames, before
# START, so its history is warm; until then, and for the reference until 4 ticks before, the cheap
# lightmap preset plays), SIZE (640x360), REF_SPP (1024; the cvar allows 4096), REF_RUNS (1),
# REF_BOUNCES (2), TIMEOUT (per engine run, 3600 s), BASELINE_MODULE (another build of our module,
# e.g. an older commit's: each of BASELINE_CONFIGS, default "path", is also captured with it, as
# "baseline:CONFIG", against the same reference). Exit 77 without the engine or game data.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tests/fidelity/engine_env.sh"
[[ $# -ge 2 ]] || { echo "usage: $0 OUT_DIR DEMO [DEMO ...]" >&2; exit 2; }
out="$1"; shift
module="${PA_MODULE:-$root/build/port/engine_glue/renderer_pathtracer_x86_64.so}"
baseline_module="${BASELINE_MODULE:-}"
[[ -z "$baseline_module" || -f "$baseline_module" ]] || { echo "no module $baseline_module" >&2; exit 2; }
compare="${PA_IMGCOMPARE:-$root/build/tests/fidelity/pa-imgcompare}"
fixed_rand="${PA_FIXED_RAND:-$root/build/tests/regress/pa_fixed_rand.so}"
configs="${CONFIGS:-path path:r_pt_temporal=0 path:r_pt_restir=1}"
frames="${FRAMES:-20}"; start="${START:-200}"; size="${SIZE:-640x360}"
warmup="${WARMUP:-16}"; ref_spp="${REF_SPP:-1024}"; ref_runs="${REF_RUNS:-1}"; ref_bounces="${REF_BOUNCES:-2}"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
command -v convert >/dev/null || { echo "needs ImageMagick's convert (scripts/setup.sh)" >&2; exit 2; }
[[ -f "$fixed_rand" ]] || { echo "missing $fixed_rand (build the tree first)" >&2; exit 2; }
[[ "$size" =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "bad SIZE $size" >&2; exit 2; }
export CAPTURE_WIDTH="${BASH_REMATCH[1]}" CAPTURE_HEIGHT="${BASH_REMATCH[2]}"
(( start > warmup && warmup >= 4 && frames >= 1 )) || { echo "need START > WARMUP >= 4 and FRAMES >= 1" >&2; exit 2; }
export PA_ENGINE_PRELOAD="$(cd "$(dirname "$fixed_rand")" && pwd)/$(basename "$fixed_rand")" PA_FIXED_RAND_SEED=1
ticks=""; for ((i = 0; i < frames; ++i)); do ticks+="$((start + 2 * i)) "; done
mkdir -p "$out"
tsv="$out/quality.tsv"
printf 'demo\tconfig\ttick\tflip\tpsnr_db\tluma_ratio\n' >"$tsv"

# capture DIR DEMO LEAD NAME VALUE [NAME VALUE ...]: the ticks of DEMO with $module; until LEAD
# ticks before the first one it runs the cheap lightmap preset (the game state does not depend on
# the renderer), then these cvars, set by the capture script itself (the engine cuts its command
# line at 1023 characters).
capture() {
  local dir="$1" demo="$2" lead="$3" work cfg tick previous status=0 latched=() i j
  shift 3
  # Latched cvars also go on the command line: they count only when set before the renderer
  # registers them. The others only after the lead, which they would slow (r_pt_spp, r_pt_scale).
  for ((i = 1; i < $#; i += 2)); do
    j=$((i + 1))
    case "${!i}" in
      r_pt_lamp_vis | r_pt_isa | r_pt_threads | r_picmip | r_intensity | r_overBrightBits | r_mapOverBrightBits)
        latched+=(+set "${!i}" "${!j}") ;;
    esac
  done
  [[ -f "$dir/frame_$(printf %04d "${ticks%% *}").tga" ]] && return 0   # kept from an earlier run
  mkdir -p "$dir"
  work="$(mktemp -d /tmp/pa-demo-quality.XXXXXX)"
  pa_engine_prepare "$work" "$module"
  mkdir -p "$work/home/baseoa/demos"
  cp "$demo" "$work/home/baseoa/demos/pa_capture.dm_71"
  cfg="$(pa_engine_cfg "$work" capture)"
  printf 'set r_pt_preset lightmap\nset r_pt_pipeline 0\nwait %d\n' "$((start - lead))" >"$cfg"
  while [[ $# -ge 2 ]]; do printf 'set %s %s\n' "$1" "$2" >>"$cfg"; shift 2; done
  previous=$((start - lead))
  for tick in $ticks; do
    printf 'wait %d\nscreenshot frame_%04d\n' "$((tick - previous))" "$tick" >>"$cfg"
    previous=$tick
  done
  printf 'wait 5\nquit\n' >>"$cfg"
  pa_engine_run "$work" "$dir/engine.log" "${TIMEOUT:-3600}" "$CAPTURE_WIDTH" "$CAPTURE_HEIGHT" pathtracer \
    +set timedemo 1 +set com_maxfps 0 +set sv_pure 0 +set con_notifytime -1 +set r_pt_stats 1 "${latched[@]}" \
    +demo pa_capture +exec capture.cfg || status=$?
  cp "$work"/home/baseoa/screenshots/frame_*.tga "$dir/" 2>/dev/null || true
  rm -rf "$work"
  [[ $status -eq 0 ]] || { echo "engine exited with status $status (log: $dir/engine.log)"; exit 1; }
  for tick in $ticks; do
    [[ -f "$dir/$(printf 'frame_%04d.tga' "$tick")" ]] || { echo "tick $tick was not captured (log: $dir/engine.log)"; exit 1; }
  done
}

for demo in "$@"; do
  source_demo="$demo"
  [[ -f "$root/tests/demos/$demo.dm_71" ]] && source_demo="$root/tests/demos/$demo.dm_71"
  [[ -f "$source_demo" ]] || { echo "no demo file $demo (a name in tests/demos or a .dm_71 path)" >&2; exit 2; }
  name="$(basename "$demo" .dm_71)"
  # The reference: REF_RUNS independent runs of REF_SPP samples, averaged per tick.
  for ((run = 1; run <= ref_runs; ++run)); do
    capture "$out/$name/ref_$run" "$source_demo" 4 r_pt_preset path r_pt_spp "$ref_spp" r_pt_temporal 0 \
      r_pt_denoise 0 r_pt_fireflies 0 r_pt_restir 0 r_pt_clamp 0 r_pt_scale 1 r_pt_bounces "$ref_bounces" \
      r_pt_seed "$((1000 * run))"
  done
  mkdir -p "$out/$name/ref"
  for tick in $ticks; do
    f="frame_$(printf %04d "$tick")"
    # -auto-orient: a TGA is stored bottom row first, which the averaged PNG would otherwise keep.
    convert "$out/$name"/ref_*/"$f.tga" -evaluate-sequence mean -auto-orient "$out/$name/ref/$f.png"
  done
  runs=()
  for config in $configs; do runs+=("$config"); done
  if [[ -n "$baseline_module" ]]; then
    for config in ${BASELINE_CONFIGS:-path}; do runs+=("baseline:$config"); done
  fi
  for config in "${runs[@]}"; do
    run_module="$module"; setting="$config"
    if [[ "$config" == baseline:* ]]; then run_module="$baseline_module"; setting="${config#baseline:}"; fi
    preset="${setting%%:*}"; cvars=(r_pt_preset "$preset")
    if [[ "$setting" == *:* ]]; then
      IFS=',' read -ra pairs <<<"${setting#*:}"
      for pair in "${pairs[@]}"; do cvars+=("${pair%%=*}" "${pair#*=}"); done
    fi
    dir="$out/$name/${config//[:=,]/_}"
    module="$run_module" capture "$dir" "$source_demo" "$warmup" "${cvars[@]}"
    for tick in $ticks; do
      f="frame_$(printf %04d "$tick")"
      "$compare" "$out/$name/ref/$f.png" "$dir/$f.tga" --json | python3 -c "
import json, sys
d = json.load(sys.stdin)
print('\t'.join([sys.argv[1], sys.argv[2], sys.argv[3], '%.4f' % d['flip'], '%.2f' % d['psnr_db'], '%.3f' % d['luma_ratio']]))" \
        "$name" "$config" "$tick" >>"$tsv"
    done
    # " frame_ms=", not max_frame_ms; "-" when the frames took under the 2 s between two stats lines.
    ms=$(awk -v p="stats $preset " 'index($0, p) && match($0, / frame_ms=[0-9.]+/) { s += substr($0, RSTART + 10, RLENGTH - 10); n++ }
      END { if (n) printf "%.0f", s / n; else print "-" }' "$dir/engine.log")
    awk -F'\t' -v d="$name" -v c="$config" -v ms="$ms" '$1 == d && $2 == c { f += $4; p += $5; l += $6; n++ }
      END { printf "%s %s: %d frames, mean FLIP %.4f, PSNR %.2f dB, luma ratio %.3f, frame_ms %s\n", d, c, n, f / n, p / n, l / n, ms }' "$tsv"
  done
done
