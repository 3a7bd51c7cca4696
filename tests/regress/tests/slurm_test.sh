#!/usr/bin/env bash
# CTest regress.slurm: a single-node Slurm on this machine (local_slurm.sh, temp dir, stopped at
# the end) runs the CI suite as 4 shards through sbatch plus the dependent merge job; the merged
# summary must equal an unsharded run's (timings aside). Then the same sharding renders the
# suite's references (pa-regress record, 4 array tasks of pa-render): byte-identical to an
# unsharded record; and batch map conversion (assets_converter, submit.sh convert, 2 array tasks).
# Usage: slurm_test.sh BUILD_DIR COMPARE_TOOL. Exit 77 without slurm-wlm/munge.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
regress="$(dirname "$here")"
build="$(realpath "$1")"; compare="$(realpath "$2")"
suite="$regress/suites/ci.json"
tmp="$(mktemp -d /tmp/pa-regress-slurm.XXXXXX)"
cleanup() { "$regress/slurm/local_slurm.sh" stop "$tmp/cluster" >/dev/null 2>&1 || true; rm -rf "$tmp"; }
trap cleanup EXIT
set +e
"$regress/slurm/local_slurm.sh" start "$tmp/cluster"
status=$?
set -e
[[ $status -eq 77 ]] && exit 77
if [[ $status -ne 0 ]]; then cat "$tmp"/cluster/*.log; exit 1; fi
export SLURM_CONF="$tmp/cluster/slurm.conf" PATH="$PATH:/usr/sbin"
opts=(--build "$build" --compare "$compare")

wait_jobs() {  # wait_jobs JOB... : until squeue no longer lists them (300 s at most)
  for _ in $(seq 1500); do
    [[ -z "$(squeue -h -j "$(IFS=,; echo "$*")" 2>/dev/null)" ]] && return 0
    sleep 0.2
  done
  echo "jobs $* still queued after 300 s"; squeue; return 1
}

read -r array merge < <("$regress/slurm/submit.sh" check "$suite" "$tmp/sharded" 4 "${opts[@]}")
echo "submitted array job $array (4 shards) and merge job $merge"
wait_jobs "$array" "$merge"
cat "$tmp"/sharded/slurm/*.out
[[ -f "$tmp/sharded/summary.json" ]] || { echo "FAIL: the merge job wrote no summary"; exit 1; }

python3 "$regress/pa-regress" check "$suite" --out "$tmp/whole" "${opts[@]}"
python3 - "$tmp/whole/summary.json" "$tmp/sharded/summary.json" <<'PY'
import json, sys
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if not k.endswith("seconds") and k not in ("shard", "merged_shards")}
    return [strip(x) for x in v] if isinstance(v, list) else v
whole, sharded = (json.load(open(p)) for p in sys.argv[1:3])
assert sharded.get("merged_shards") == 4, sharded.get("merged_shards")
assert strip(whole) == strip(sharded), "merged 4-shard summary differs from the unsharded run"
print(f"merged summary of 4 Slurm shards equals the unsharded run ({len(whole['cases'])} cases, exit {whole['exit_status']})")
PY

# High-spp reference renders through the same sharding: pa-render in 4 array tasks.
array="$("$regress/slurm/submit.sh" record "$suite" "$tmp/refs-sharded" 4 "${opts[@]}")"
wait_jobs "$array"
python3 "$regress/pa-regress" record "$suite" --refs "$tmp/refs-whole" "${opts[@]}"
for f in "$tmp"/refs-whole/*/frame.*; do
  cmp "$f" "$tmp/refs-sharded/${f#"$tmp"/refs-whole/}" || { echo "FAIL: $f differs when recorded through Slurm"; exit 1; }
done
echo "references recorded by 4 Slurm array tasks are byte-identical to an unsharded record"

# Batch map conversion through the same sharding: 4 maps in 2 array tasks plus the merge job that
# checks every .glb, byte-identical to converting them in one process.
game="${PA_GAME_DIR:-/usr/share/games/openarena/baseoa}"
converter="$build/assets_converter/assets_converter"
if [[ -x "$converter" && -d "$game" ]]; then
  maps=(oa_ctf2 aggressor q3dm6ish oa_bases5)
  read -r array merge < <(PA_CONVERTER="$converter" "$regress/slurm/submit.sh" convert "$game" "$tmp/glb-sharded" 2 \
                          $(printf -- '--map %s ' "${maps[@]}"))
  wait_jobs "$array" "$merge"
  cat "$tmp"/glb-sharded/slurm/*.out
  python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); assert s["converted"] == s["maps"] == 4, s' \
    "$tmp/glb-sharded/convert-summary.json"
  "$converter" --game "$game" $(printf -- '--map %s ' "${maps[@]}") -o "$tmp/glb-whole" >/dev/null
  for m in "${maps[@]}"; do
    cmp "$tmp/glb-whole/$m.glb" "$tmp/glb-sharded/$m.glb" || { echo "FAIL: $m.glb differs when converted through Slurm"; exit 1; }
  done
  echo "4 maps converted by 2 Slurm array tasks are byte-identical to one unsharded conversion"
else
  echo "map conversion not checked: no $converter or no game data in $game"
fi
echo PASS
