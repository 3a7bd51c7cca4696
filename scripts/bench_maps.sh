#!/usr/bin/env bash
# scripts/bench_maps.sh [--bench PATH]... [--runs N] [--maps "A B ..."] [--isas "native avx2"]
#                       [--jsonl FILE] [-- extra bench arguments]
# The BVH against Embree on OpenArena maps, both ISAs: per map, ISA and bench binary the medians
# over N runs of the ours / Embree ratios (incoherent, shadow, primary packets, lamp-shadow
# packets, build), then the geometric mean and the worst map per column (docs/performance.md,
# "Rays on ten maps").
# Each call is `bench --scene MAP.glb --threads 1 --reps 5 --json --no-frames --rays 262144`
# (plus `--isa avx2` for the AVX2 column; the bench times 15 builds a side, interleaved, and its
# build ratio is the median of theirs); runs alternate maps, ISAs and binaries, so a load spike
# spreads over all of them.
#   --bench PATH   bench binary (default build/renderer/bench/bench); repeat to A/B binaries
#   --runs N       repetitions (default 3)
#   --maps "..."   map names (default: the 5 smallest and 5 largest installed maps by the
#                  triangles assets_converter writes)
#   --isas "..."   native (AVX-512 16-wide where the CPU has it) and/or avx2 (default both)
#   --jsonl FILE   also keep every bench answer, one JSON line each, tagged with run/isa/bench
# Maps are converted to out/maps/NAME.glb on first use (needs the openarena-data package).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
benches=()
runs=3
maps="fan oa_bases3cl ps37ctf2 oa_bases5 oa_bases3 oacmpdm9 oa_thor czest2ctf pul1ctf oacmpdm8"
isas="native avx2"
jsonl=""
extra=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --bench) benches+=("$2"); shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --maps) maps="$2"; shift 2 ;;
    --isas) isas="$2"; shift 2 ;;
    --jsonl) jsonl="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) echo "bench_maps: unknown argument $1" >&2; exit 2 ;;
  esac
done
[[ ${#benches[@]} -gt 0 ]] || benches=("$root/build/renderer/bench/bench")
for b in "${benches[@]}"; do
  [[ -x "$b" ]] || { echo "bench_maps: no bench at $b (build the bench target)" >&2; exit 1; }
done

mkdir -p "$root/out/maps"
for m in $maps; do
  if [[ ! -f "$root/out/maps/$m.glb" ]]; then
    converter="$root/build/assets_converter/assets_converter"
    [[ -x "$converter" ]] || { echo "bench_maps: no converter to make $m.glb" >&2; exit 1; }
    "$converter" --game /usr/share/games/openarena/baseoa --map "$m" -o "$root/out/maps" > /dev/null
  fi
done

lines="$(mktemp)"
trap 'rm -f "$lines"' EXIT
echo "bench_maps: $(date -u '+%F %H:%M UTC'), load $(cut -d' ' -f1-3 /proc/loadavg); $("$root/scripts/machine.sh")" >&2
for ((run = 1; run <= runs; ++run)); do
  for m in $maps; do
    for isa in $isas; do
      for ((b = 0; b < ${#benches[@]}; ++b)); do
        isa_args=()
        [[ "$isa" == avx2 ]] && isa_args=(--isa avx2)
        "${benches[$b]}" --scene "$root/out/maps/$m.glb" --threads 1 --reps 5 --json --no-frames \
          --rays 262144 "${isa_args[@]}" "${extra[@]}" |
          python3 -c 'import json, sys; d = json.load(sys.stdin); d.update(run=int(sys.argv[1]), map=sys.argv[2], isa=sys.argv[3], bench=int(sys.argv[4])); print(json.dumps(d))' \
            "$run" "$m" "$isa" "$b" >> "$lines"
      done
    done
  done
  echo "bench_maps: run $run of $runs done, load $(cut -d' ' -f1-3 /proc/loadavg)" >&2
done
[[ -n "$jsonl" ]] && cp "$lines" "$jsonl"

python3 - "$lines" "${benches[@]}" <<'EOF'
import json, math, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
names = sys.argv[2:]
cols = [("incoherent", "incoherent_ratio", max), ("shadow", "shadow_ratio", max),
        ("primary", "primary_ratio", max), ("lamp", "lamp_shadow_ratio", max), ("build", "build_ratio", min)]
maps = list(dict.fromkeys(r["map"] for r in rows))
isas = list(dict.fromkeys(r["isa"] for r in rows))
for b, name in enumerate(names):
    for isa in isas:
        print(f"\nbench {name}, isa {isa}: medians of ours / Embree over runs")
        print(f"{'map':<14}{'triangles':>10}" + "".join(f"{c[0]:>12}" for c in cols))
        med = {}
        for m in maps:
            sel = [r for r in rows if r["map"] == m and r["isa"] == isa and r["bench"] == b]
            # A column an older bench binary does not print reads nan.
            med[m] = [statistics.median(r.get(c[1], math.nan) for r in sel) for c in cols]
            print(f"{m:<14}{sel[0]['triangles']:>10}" + "".join(f"{v:>12.3f}" for v in med[m]))
        geo = [math.exp(statistics.fmean(math.log(med[m][i]) for m in maps)) for i in range(len(cols))]
        print(f"{'geomean':<24}" + "".join(f"{v:>12.3f}" for v in geo))
        worst = []
        for i, c in enumerate(cols):
            if any(math.isnan(med[m][i]) for m in maps):
                worst.append("-")
                continue
            bad = min(maps, key=lambda m: med[m][i]) if c[2] is max else max(maps, key=lambda m: med[m][i])
            worst.append(f"{bad} {med[bad][i]:.3f}")
        print(f"{'worst':<24}" + "".join(f"{w:>22}" for w in worst))
EOF
