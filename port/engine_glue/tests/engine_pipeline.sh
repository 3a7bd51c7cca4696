#!/usr/bin/env bash
# r_pt_pipeline in the real engine: with it, each frame shows the world view of the frame before
# (traced while the game went on), so a timedemo's tick N+2 (the next rendered frame: a timedemo
# runs two command-buffer ticks a frame) must show the world picture that tick N shows without it.
#   engine_pipeline.sh MODULE IMGCOMPARE FIXED_RAND [DEMO] [TICKS]
# Defaults: tests/demos/dm1_ffa.dm_71, ticks "100 160 220"; the lightmap preset, the game's
# random numbers fixed (FIXED_RAND: tests/regress's pa_fixed_rand.so) so that runs repeat.
#  1. Without the HUD (cg_draw2D 0): pipelined tick N+2 has the same bytes as tick N unpipelined,
#     and pipelined tick N differs from it (the pipeline is on: its picture is a frame older).
#  2. With the HUD (its model views traced while the world view is): pipelined tick N+2 against
#     tick N unpipelined differs only by one frame of HUD: PSNR >= 30 dB.
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
module="$1"; compare="$2"; fixed_rand="$3"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
demo="${4:-$root/tests/demos/dm1_ffa.dm_71}"
ticks="${5:-100 160 220}"
source "$root/tests/fidelity/engine_env.sh"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }

work="$(mktemp -d /tmp/pa-pipeline.XXXXXX)"
trap '[[ -n "${PA_KEEP:-}" ]] || rm -rf "$work"' EXIT
later=""
for t in $ticks; do later+="$((t + 2)) "; done

capture() {   # capture NAME TICKS PIPELINE [engine args]: frame_NNNN.tga in $work/NAME
  local name="$1" at="$2" pipeline="$3"
  shift 3
  PA_ENGINE_PRELOAD="$fixed_rand" PA_FIXED_RAND_SEED=1 CAPTURE_DEMO="$demo" PA_CAPTURE_PIPELINE="$pipeline" \
    "$root/tests/fidelity/capture_frames.sh" "$work/$name" pathtracer "$module" "$at" \
    +set r_pt_preset lightmap "$@" >"$work/$name.out" 2>&1 || { cat "$work/$name.out"; exit 1; }
}
capture own "$ticks" 0 +set cg_draw2D 0
capture next "$later" 1 +set cg_draw2D 0
capture same "$ticks" 1 +set cg_draw2D 0
capture hud_own "$ticks" 0
capture hud_next "$later" 1

status=0
frame() { printf '%s/%s/frame_%04d.tga' "$work" "$1" "$2"; }
for t in $ticks; do
  n=$((t + 2))
  for f in "$(frame own "$t")" "$(frame next "$n")" "$(frame same "$t")" "$(frame hud_own "$t")" "$(frame hud_next "$n")"; do
    [[ -f "$f" ]] || { echo "FAIL: $f was not written"; exit 1; }
  done
  if cmp -s "$(frame own "$t")" "$(frame next "$n")"; then
    echo "tick $t: pipelined tick $n shows the same bytes"
  else
    echo "FAIL: pipelined tick $n differs from tick $t unpipelined: $("$compare" "$(frame own "$t")" "$(frame next "$n")" | head -n 1)"
    status=1
  fi
  if cmp -s "$(frame own "$t")" "$(frame same "$t")"; then
    echo "FAIL: pipelined tick $t shows tick $t's own world view: is the pipeline on?"
    status=1
  fi
  metrics="$("$compare" "$(frame hud_own "$t")" "$(frame hud_next "$n")" | head -n 1)"
  psnr="$(sed -n 's/^psnr_db=\([0-9.]*\).*/\1/p' <<<"$metrics")"
  echo "tick $t with the HUD: pipelined tick $n against tick $t: $metrics"
  awk -v p="$psnr" 'BEGIN { exit !(p >= 30) }' || { echo "FAIL: PSNR $psnr dB < 30"; status=1; }
done
exit "$status"
