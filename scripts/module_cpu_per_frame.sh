#!/usr/bin/env bash
# scripts/module_cpu_per_frame.sh MODULE DEMO PRESET [MESSAGES]: CPU milliseconds per frame spent
# in our module's own code while the game plays a demo: `perf record -e cpu-clock -F 999` of a
# scripts/engine_bench.sh run (every process and thread it starts), the samples that fall in
# renderer_pathtracer_x86_64.so counted and divided by the preset's frames (loading included: the
# same for two modules on one map). Unlike fps or the process's CPU time (scripts/cpu_per_frame.sh)
# it leaves out what waits or spins (TBB's idle workers, the X server, llvmpipe) and so moves little
# with other jobs' load: A/B two modules by alternating them. The game's random numbers are fixed
# (tests/regress's pa_fixed_rand.so, built with the tests) so that both play the same frames.
# PRESET may carry cvars as in engine_bench ("path:r_pt_temporal=0"); MESSAGES defaults to 300.
# Needs perf (Debian linux-perf) and what engine_bench needs; exit 77 without them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
[[ $# -ge 3 ]] || { echo "usage: $0 MODULE DEMO PRESET [MESSAGES]" >&2; exit 2; }
module="$(realpath "$1")"; demo="$2"; preset="$3"; messages="${4:-300}"
command -v perf >/dev/null || { echo "skipped: perf is missing (apt-get install linux-perf)" >&2; exit 77; }
fixed="$root/build/tests/regress/pa_fixed_rand.so"
[[ -f "$fixed" ]] || { echo "$fixed is missing: build the tests first" >&2; exit 2; }

work="$(mktemp -d /tmp/pa-module-cpu.XXXXXX)"
trap 'rm -rf "$work"' EXIT
status=0
PA_ENGINE_PRELOAD="$fixed" PA_FIXED_RAND_SEED=1 \
  perf record -q -F 999 -e cpu-clock -o "$work/perf.data" -- \
  "$root/scripts/engine_bench.sh" --module "$module" --demos "$demo" --presets "$preset" --messages "$messages" \
  >"$work/bench.log" 2>&1 || status=$?
[[ $status -eq 77 ]] && { echo "skipped: engine or game data missing" >&2; exit 77; }
frames="$(awk -v p="$preset" '$1 == p && NF == 5 { print $2; exit }' "$work/bench.log")"   # the row is named by the whole preset
fps="$(awk -v p="$preset" '$1 == p && NF == 5 { print $4; exit }' "$work/bench.log")"
if [[ $status -ne 0 || -z "$frames" ]]; then cat "$work/bench.log" >&2; echo "engine_bench failed" >&2; exit 1; fi
samples="$(perf report -i "$work/perf.data" --sort dso --stdio -q -n 2>/dev/null |
  awk '/renderer_pathtracer/ { print $2; exit }')"
awk -v s="${samples:-0}" -v f="$frames" -v fps="$fps" -v d="$demo" -v p="$preset" -v m="$(basename "$module")" \
  'BEGIN { printf "%s %s %s module_cpu_ms_per_frame %.2f (samples %d, frames %d, fps %s)\n", m, d, p, s / 999 * 1000 / f, s, f, fps }'
