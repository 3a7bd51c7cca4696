#!/usr/bin/env bash
# scripts/profile_game.sh OUT.data DEMO PRESET [options]: a `perf record` of the game playing a demo
# with our module, in its steady state: scripts/engine_bench.sh plays DEMO (opengl1 first, then
# PRESET), and once our module's game has run for --delay seconds its process (every thread:
# ours, the engine's, llvmpipe's) is sampled for --seconds; then the game and the bench are
# stopped. Read it with `perf report -i OUT.data --no-children --sort dso,sym`.
#   --delay S      seconds of play before sampling starts (default 6: past loading)
#   --seconds S    seconds sampled (default 10)
#   --module PATH  our module (default build/port/engine_glue/renderer_pathtracer_x86_64.so)
#   --messages N   demo messages played (default 600: long enough to outlast the sampling)
#   --call-graph   with call stacks (perf's dwarf unwinding; large files, a few seconds suffice)
# PRESET may carry cvars as in engine_bench ("path:r_pt_temporal=0"). Needs perf (Debian
# linux-perf) and what engine_bench needs; exit 77 without them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
[[ $# -ge 3 ]] || { echo "usage: $0 OUT.data DEMO PRESET [--delay S] [--seconds S] [--module PATH] [--messages N] [--call-graph]" >&2; exit 2; }
out="$1"; demo="$2"; preset="$3"; shift 3
delay=6; seconds=10; messages=600; module="$root/build/port/engine_glue/renderer_pathtracer_x86_64.so"
graph=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --delay) delay="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --module) module="$2"; shift 2 ;;
    --messages) messages="$2"; shift 2 ;;
    --call-graph) graph=(--call-graph dwarf,16384); shift ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
command -v perf >/dev/null || { echo "skipped: perf is missing (apt-get install linux-perf)" >&2; exit 77; }

descendants() { local p; for p in $(pgrep -P "$1" || true); do echo "$p"; descendants "$p"; done; }

log="$(mktemp /tmp/pa-profile-game.XXXXXX)"
"$root/scripts/engine_bench.sh" --module "$module" --demos "$demo" --presets "$preset" --messages "$messages" \
  >"$log" 2>&1 &
bench=$!
game=""
stop() {   # the bench's children first, then the game itself (it outlives a stopped bench)
  kill -- $(descendants "$bench") "$bench" 2>/dev/null || true
  [[ -n "$game" ]] && kill -9 "$game" 2>/dev/null || true
  wait "$bench" 2>/dev/null || true
}
trap stop EXIT
while kill -0 "$bench" 2>/dev/null && [[ -z "$game" ]]; do   # our module's game (opengl1's comes first)
  for p in $(descendants "$bench"); do
    [[ "$(cat "/proc/$p/comm" 2>/dev/null)" == ioquake3 ]] || continue
    grep -q renderer_pathtracer "/proc/$p/maps" 2>/dev/null && { game=$p; break; }
  done
  sleep 0.1
done
if [[ -z "$game" ]]; then
  status=0; wait "$bench" || status=$?
  cat "$log" >&2; rm -f "$log"
  [[ $status -eq 77 ]] && exit 77
  echo "our module's game did not start" >&2; exit 1
fi
sleep "$delay"
kill -0 "$game" 2>/dev/null || { cat "$log" >&2; rm -f "$log"; echo "the demo ended before sampling: raise --messages" >&2; exit 1; }
perf record -e cpu-clock -F 999 "${graph[@]}" -p "$game" -o "$out" -- sleep "$seconds" 2>&1 | tail -n 1
rm -f "$log"
echo "profile of $demo with $preset in $out"
