#!/usr/bin/env bash
# scripts/instructions_per_frame.sh [options] MAP.bsp [-- PA_RENDER_ARGS...]: the instructions one
# steady frame of `pa-render` executes, counted by valgrind's callgrind: each binary renders the
# map twice (FIRST and LAST frames), and the difference of the two counts over LAST - FIRST is a
# frame's, loading and the first frames left out. The count repeats within 0.03% from run to run
# (one thread, fixed seeds), so it sizes a change of work that wall time on a shared 2-core machine
# cannot resolve (runs of one binary move by 5-50% there). It is not time: valgrind runs the
# AVX2 kernels (it has no AVX-512), and work that waits on latency or memory costs more than its
# instructions (docs/performance.md, "Method"). Prints, per binary, the instructions per frame
# and their ratio to the first binary's, then the functions with the most (self) instructions per
# frame side by side.
#   --bin PATH       a pa-render binary (repeatable; default build/renderer/cli/pa-render)
#   --frames "F L"   the two frame counts (default "2 6")
#   --top N          functions listed (default 25)
# Default pa-render arguments (the game's `direct` frame, one thread): --integrator direct
# --play temporal --roulette-start 1 --baked-path-end --denoise --width 320 --height 180 --spp 1;
# arguments after -- replace them (--threads 1 and --frames are always set).
# Needs valgrind (Debian `valgrind`); exit 77 without it.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bins=()
frames="2 6"
top=25
while (($#)); do
  case "$1" in
    --bin) bins+=("$2"); shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --top) top="$2"; shift 2 ;;
    --) break ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    -*) echo "instructions_per_frame: unknown option $1" >&2; exit 2 ;;
    *) [[ -z "${map:-}" ]] || { echo "instructions_per_frame: one map only" >&2; exit 2; }; map="$1"; shift ;;
  esac
done
[[ -n "${map:-}" ]] || { echo "usage: $0 [--bin PATH]... [--frames \"F L\"] MAP.bsp [-- ARGS...]" >&2; exit 2; }
args=(--integrator direct --play temporal --roulette-start 1 --baked-path-end --denoise --width 320 --height 180 --spp 1)
if (($#)) && [[ "$1" == "--" ]]; then shift; args=("$@"); fi
((${#bins[@]})) || bins=("$root/build/renderer/cli/pa-render")
command -v valgrind >/dev/null && command -v callgrind_annotate >/dev/null ||
  { echo "instructions_per_frame: needs valgrind (apt-get install valgrind)" >&2; exit 77; }
read -r first last <<< "$frames"
((last > first)) || { echo "instructions_per_frame: --frames needs F < L" >&2; exit 2; }
for b in "${bins[@]}"; do [[ -x "$b" ]] || { echo "instructions_per_frame: no binary $b" >&2; exit 1; }; done

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# The two counts of one binary run side by side (two cores); binaries one after the other.
for i in "${!bins[@]}"; do
  pids=()
  for n in "$first" "$last"; do
    valgrind --tool=callgrind --callgrind-out-file="$work/$i.$n.out" "${bins[$i]}" "$map" \
      -o "$work/$i.$n.png" "${args[@]}" --threads 1 --frames "$n" -q > "$work/$i.$n.log" 2>&1 &
    pids+=($!)
  done
  for pid in "${pids[@]}"; do
    wait "$pid" || { echo "instructions_per_frame: a run of ${bins[$i]} failed (logs in $work)" >&2; trap - EXIT; exit 1; }
  done
done

python3 - "$work" "$first" "$last" "$top" "${bins[@]}" <<'EOF'
import re, subprocess, sys
work, first, last, top = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
bins = sys.argv[5:]

def counts(path):
    """Self instructions per function (summed over the source files its code came from)."""
    out = subprocess.run(['callgrind_annotate', '--inclusive=no', '--auto=no', '--threshold=100', path],
                         capture_output=True, text=True, check=True).stdout
    total, per = 0, {}
    for line in out.splitlines():
        m = re.match(r'\s*([\d,]+)\s+\([^)]*\)\s+(.*)$', line)
        if not m:
            continue
        value, name = int(m.group(1).replace(',', '')), m.group(2)
        if name.startswith('PROGRAM TOTALS'):
            total = value
            continue
        name = re.sub(r' \[[^\]]*\]$', '', name)          # the object file
        function = name.split(':', 1)[1] if ':' in name else name
        per[function] = per.get(function, 0) + value
    return total, per

frames = last - first
rows = []
for i, b in enumerate(bins):
    t0, f0 = counts(f'{work}/{i}.{first}.out')
    t1, f1 = counts(f'{work}/{i}.{last}.out')
    rows.append(((t1 - t0) / frames, {k: (f1.get(k, 0) - f0.get(k, 0)) / frames for k in set(f0) | set(f1)}))
base = rows[0][0]
print(f'instructions per frame (callgrind, frames {first}..{last}):')
for b, (t, _) in zip(bins, rows):
    print(f'  {t / 1e6:10.2f} M  x{t / base:.4f}  {b}')

def short(f):
    """A function's name without its parameter list, qualifiers and return type."""
    s = f.strip().replace(') const::', ')::')   # a lambda inside a const member function
    end = s.rfind(')')
    if end >= 0:   # the last top-level parameter list
        depth = 0
        for i in range(end, -1, -1):
            depth += s[i] == ')'
            depth -= s[i] == '('
            if depth == 0:
                s = s[:i]
                break
    depth, cut = 0, 0
    for i, c in enumerate(s):
        depth += c in '<('
        depth -= c in '>)'
        if c == ' ' and depth == 0:
            cut = i + 1
    return s[cut:]

names = sorted(rows[0][1], key=lambda k: -abs(rows[0][1][k]))[:top]
print('M per frame: ' + ' | '.join(f'[{i}]' for i in range(len(bins))) + '  function')
for k in names:
    print('  ' + ' | '.join(f'{r[1].get(k, 0) / 1e6:8.2f}' for r in rows) + '  ' + short(k)[:100])
EOF
