#!/usr/bin/env bash
# Allocations in the steady state of play: Debian's ioquake3 under xvfb-run plays a recorded demo
# with our module (timedemo 1, 640x360), warms up for WARMUP command-buffer ticks (a timedemo
# runs about two a frame: 600 ticks is about 300 of a 600-frame demo, by when every kind of
# entity, effect and HUD view has been shown), then the module's pt_allocations command counts
# its heap allocations (operator new and the malloc family of the module's code,
# allocation_counter.h) over the next FRAMES frames, for each preset given.
#   engine_allocations.sh MODULE [PRESETS] [DEMO] [WARMUP] [FRAMES]
# PRESETS: "preset[:budget] ..." where budget is the most allocations per frame accepted, on
# average over the window (default 0; a fraction such as 0.1 allows 10 in 100 frames).
# Defaults: "lightmap direct path", tests/demos/dm1_ffa, 600, 100. On failure the log shows a
# backtrace of the first allocations of the window (pt_allocations trace; PA_ALLOCATION_TRACES=N
# traces more, PA_KEEP=1 keeps the engine logs) to find them with addr2line -f -C -e MODULE.
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
module="$1"
presets="${2:-lightmap direct path}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)"
demo="${3:-$root/tests/demos/dm1_ffa.dm_71}"
warmup="${4:-600}"
frames="${5:-100}"
source "$root/tests/fidelity/engine_env.sh"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }

work="$(mktemp -d /tmp/pa-allocations.XXXXXX)"
trap '[[ -n "${PA_KEEP:-}" ]] || rm -rf "$work"' EXIT
pa_engine_prepare "$work" "$module"
mkdir -p "$work/home/baseoa/demos"
# The demo is cut well past the window so that it is still playing when the count ends.
pa_demo_truncate "$work/home/baseoa/demos/allocations.dm_71" $((warmup + frames + 200)) "$demo" >/dev/null
# In a timedemo the engine runs its command buffer about twice per rendered frame: the window
# waits 2 x FRAMES ticks, and the module reports the frames it actually drew (checked below).
cat >"$(pa_engine_cfg "$work" allocations)" <<CFG
wait $warmup
pt_allocations trace ${PA_ALLOCATION_TRACES:-20}
wait $((2 * frames))
pt_allocations
wait 2
quit
CFG

status=0
for entry in $presets; do
  preset="${entry%%:*}"
  budget=0
  [[ "$entry" == *:* ]] && budget="${entry#*:}"
  [[ "$budget" =~ ^[0-9]+(\.[0-9]+)?$ ]] || { echo "FAIL $preset: bad budget '$budget'"; status=1; continue; }
  log="$work/$preset.log"
  pa_engine_run "$work" "$log" 300 640 360 pathtracer +set r_pt_preset "$preset" +set timedemo 1 \
    +set r_pt_threads 2 +demo allocations +exec allocations || true
  if ! pa_engine_used_renderer "$log" pathtracer; then
    echo "FAIL $preset: the engine did not run our module"; tail -20 "$log"; status=1; continue
  fi
  result="$(grep -o 'pathtracer: allocations=[0-9]* frames=[0-9]*' "$log" | tail -1 || true)"
  [[ -n "$result" ]] || { echo "FAIL $preset: no pt_allocations result"; tail -20 "$log"; status=1; continue; }
  count="$(sed 's/.*allocations=\([0-9]*\).*/\1/' <<<"$result")"
  counted_frames="$(sed 's/.*frames=\([0-9]*\).*/\1/' <<<"$result")"
  if [[ "$counted_frames" -lt "$frames" ]]; then
    echo "FAIL $preset: counted only $counted_frames frames (the demo ended early?)"; status=1
  elif awk -v c="$count" -v b="$budget" -v f="$counted_frames" 'BEGIN { exit !(c > b * f) }'; then
    echo "FAIL $preset: $count allocations in $counted_frames steady-state frames (budget $budget per frame)"
    grep -A14 "pathtracer: allocation at" "$log" | head -120 || true
    status=1
  else
    echo "ok $preset: $count allocations in $counted_frames steady-state frames (budget $budget per frame)"
  fi
done
exit $status
