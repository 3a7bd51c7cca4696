#!/usr/bin/env bash
# CTest regress.capture_repeat: a demo capture of one module is the same bytes in every run.
# Captures dm3_rockets ticks 60, 64, 140 and 220 (tests/fidelity/capture_frames.sh, lightmap
# preset, game seed 1 through pa_fixed_rand.so, the film EXRs too) twice: once with 2 threads, once
# with 1 thread and the engine stalled for PA_STALL_MS (4 s) while it writes the tick-60 screenshot
# (pa_stall_on_write.so), as another job on the machine would stall it. The demo clock of a
# timedemo does not move during the stall, the engine's wall clock does, so anything in the picture
# that follows the wall clock (such as the console's notify lines, shown for 3 s of it, which the
# capture helper hides) or the thread count makes the two captures differ. Every TGA and EXR must
# be identical.
# Usage: capture_repeat_test.sh MODULE PA_FIXED_RAND PA_STALL_ON_WRITE PA_IMGCOMPARE
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../../.." && pwd)"
source "$root/tests/fidelity/engine_env.sh"
module="$1"; fixed_rand="$2"; stall="$3"; compare="$4"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
out="$(mktemp -d /tmp/pa-capture-repeat.XXXXXX)"
trap 'rm -rf "$out"' EXIT
ticks="60 64 140 220"
stall_ms="${PA_STALL_MS:-4000}"
args=(+set r_pt_preset lightmap +set r_pt_captureExr 1)
export PA_FIXED_RAND_SEED=1 CAPTURE_DEMO="$root/tests/demos/dm3_rockets.dm_71"

PA_ENGINE_PRELOAD="$fixed_rand" "$root/tests/fidelity/capture_frames.sh" "$out/steady" pathtracer "$module" \
  "$ticks" "${args[@]}" +set r_pt_threads 2 || exit $?
PA_ENGINE_PRELOAD="$fixed_rand:$stall" PA_STALL_ON_WRITE=frame_0060 PA_STALL_MS="$stall_ms" \
  "$root/tests/fidelity/capture_frames.sh" "$out/stalled" pathtracer "$module" "$ticks" "${args[@]}" \
  +set r_pt_threads 1 || exit $?
# The stall must have happened, or the second run tests nothing the first does not.
grep -q "pa_stall_on_write: stalled" "$out/stalled/engine.log" || { echo "FAIL: the engine did not stall"; exit 1; }

failed=0 compared=0
for tick in $ticks; do
  for ext in tga exr; do
    name="$(printf 'frame_%04d.%s' "$tick" "$ext")"
    [[ -f "$out/steady/$name" && -f "$out/stalled/$name" ]] || { echo "FAIL: $name missing"; failed=1; continue; }
    compared=$((compared + 1))
    if cmp -s "$out/steady/$name" "$out/stalled/$name"; then
      echo "tick $tick $ext: identical"
    else
      failed=1
      figures=""
      [[ "$ext" == tga ]] && figures="$("$compare" "$out/steady/$name" "$out/stalled/$name" | cut -d' ' -f1,4,8,9)"
      echo "FAIL: tick $tick $ext differs between the two runs $figures"
    fi
  done
done
echo "$compared files compared, stall ${stall_ms} ms, 2 threads against 1"
exit $failed
