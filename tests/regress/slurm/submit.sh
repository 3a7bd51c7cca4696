#!/usr/bin/env bash
# submit.sh check|record SUITE DIR N [pa-regress options...]
# submit.sh convert GAME_DIR OUT_DIR N [--map NAME ...] [assets_converter options...]
# Submits a pa-regress suite to Slurm as a job array of N shards (pa-regress-shard.sbatch) and,
# for check, a merge job that starts when every shard has ended (afterany: shards that find
# regressions exit 1 and must still be merged). DIR must be on a file system all nodes share.
# convert: batch map conversion split the same way (convert-shard.sbatch: the given maps, or
# every map of GAME_DIR, each task every N-th) plus a merge job that checks every NAME.glb
# (convert-merge.sbatch); the converter is PA_CONVERTER (default: this checkout's build).
# Prints "ARRAY_JOB_ID [MERGE_JOB_ID]". Extra sbatch options: PA_REGRESS_SBATCH_OPTS (e.g.
# "--partition=render --cpus-per-task=8 --time=30").
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if [[ "${1:-}" == convert ]]; then
  game="$(realpath "$2")"; out="$(realpath -m "$3")"; n="$4"; shift 4
  [[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "N must be a positive integer"; exit 2; }
  converter="$(realpath "${PA_CONVERTER:-$here/../../../build/assets_converter/assets_converter}")"
  mkdir -p "$out/slurm"
  maps=(); rest=()
  while [[ $# -gt 0 ]]; do
    if [[ "$1" == --map && $# -ge 2 ]]; then maps+=("$2"); shift 2; else rest+=("$1"); shift; fi
  done
  if [[ ${#maps[@]} -gt 0 ]]; then printf '%s\n' "${maps[@]}" >"$out/slurm/maps.txt"
  else "$converter" --game "$game" --list >"$out/slurm/maps.txt"; fi
  # shellcheck disable=SC2086
  array="$(sbatch --parsable ${PA_REGRESS_SBATCH_OPTS:-} --array="1-$n" --output="$out/slurm/convert-%a.out" \
    "$here/convert-shard.sbatch" "$converter" "$game" "$out" "$out/slurm/maps.txt" "${rest[@]}")"
  array="${array%%;*}"
  # shellcheck disable=SC2086
  merge="$(sbatch --parsable ${PA_REGRESS_SBATCH_OPTS:-} --dependency="afterany:$array" --output="$out/slurm/merge.out" \
    "$here/convert-merge.sbatch" "$out" "$out/slurm/maps.txt")"
  echo "$array ${merge%%;*}"
  exit 0
fi
command="$1"; suite="$(realpath "$2")"; dir="$(realpath -m "$3")"; n="$4"; shift 4
[[ "$command" == check || "$command" == record ]] || { echo "usage: submit.sh check|record SUITE DIR N [options] | convert GAME_DIR OUT_DIR N [--map NAME ...]"; exit 2; }
[[ "$n" =~ ^[1-9][0-9]*$ ]] || { echo "N must be a positive integer"; exit 2; }
tool="$(realpath "$here/../pa-regress")"
mkdir -p "$dir/slurm"
# shellcheck disable=SC2086
array="$(sbatch --parsable ${PA_REGRESS_SBATCH_OPTS:-} --array="1-$n" --output="$dir/slurm/shard-%a.out" \
  "$here/pa-regress-shard.sbatch" "$tool" "$command" "$suite" "$dir" "$@")"
array="${array%%;*}"
if [[ "$command" == record ]]; then echo "$array"; exit 0; fi
# shellcheck disable=SC2086
merge="$(sbatch --parsable ${PA_REGRESS_SBATCH_OPTS:-} --dependency="afterany:$array" --output="$dir/slurm/merge.out" \
  "$here/pa-regress-merge.sbatch" "$tool" "$dir")"
echo "$array ${merge%%;*}"
