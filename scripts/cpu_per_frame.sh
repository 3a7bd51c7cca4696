#!/usr/bin/env bash
# scripts/cpu_per_frame.sh MODULE DEMO PRESET [N1 N2]: CPU milliseconds per frame of our module in
# the game (user + system time of the traced game's process, all its threads, llvmpipe's included)
# over the frames between message N1 (default 30) and N2 (default 150) of a demo, from two
# scripts/engine_bench.sh runs capped at N1 and at N2 messages. Unlike fps it holds on a machine
# that other jobs share; A/B two modules by alternating them. PRESET may carry cvars as in
# engine_bench ("path:r_pt_temporal=0"). Exit 77 without the engine or the game data.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
[[ $# -ge 3 ]] || { echo "usage: $0 MODULE DEMO PRESET [N1 N2]" >&2; exit 2; }
module="$1"; demo="$2"; preset="$3"; n1="${4:-30}"; n2="${5:-150}"
(( n2 > n1 && n1 > 0 )) || { echo "need N2 > N1 > 0" >&2; exit 2; }

descendants() { local p; for p in $(pgrep -P "$1" || true); do echo "$p"; descendants "$p"; done; }

# run N: prints "CPU_TICKS FRAMES" of the preset's run capped at N messages.
run() {
  local log bench pid="" last=0 t p frames status=0
  log="$(mktemp /tmp/pa-cpu-per-frame.XXXXXX)"
  "$root/scripts/engine_bench.sh" --module "$module" --demos "$demo" --presets "$preset" --messages "$1" \
    >"$log" 2>&1 &
  bench=$!
  while kill -0 "$bench" 2>/dev/null; do
    if [[ -z "$pid" ]]; then   # our module's game (engine_bench runs opengl1's first)
      for p in $(descendants "$bench"); do
        [[ "$(cat "/proc/$p/comm" 2>/dev/null)" == ioquake3 ]] || continue
        grep -q renderer_pathtracer "/proc/$p/maps" 2>/dev/null && { pid=$p; break; }
      done
    fi
    if [[ -n "$pid" ]] && t="$(awk '{print $14 + $15}' "/proc/$pid/stat" 2>/dev/null)"; then last=$t; fi
    sleep 0.05
  done
  wait "$bench" || status=$?
  frames="$(awk -v p="$preset" '$1 == p && NF == 5 { print $2; exit }' "$log")"   # the row is named by the whole preset
  if [[ $status -eq 77 ]]; then rm -f "$log"; echo "skipped: engine or game data missing" >&2; exit 77; fi
  if [[ $status -ne 0 || -z "$frames" || -z "$pid" ]]; then
    cat "$log" >&2; rm -f "$log"; echo "engine_bench failed" >&2; exit 1
  fi
  rm -f "$log"
  echo "$last $frames"
}

first="$(run "$n1")"
second="$(run "$n2")"
read -r c1 f1 <<<"$first"
read -r c2 f2 <<<"$second"
awk -v c1="$c1" -v c2="$c2" -v f1="$f1" -v f2="$f2" -v hz="$(getconf CLK_TCK)" -v d="$demo" -v p="$preset" \
  'BEGIN { printf "%s %s cpu_ms_per_frame %.2f (frames %d..%d)\n", d, p, (c2 - c1) * 1000 / hz / (f2 - f1), f1, f2 }'
