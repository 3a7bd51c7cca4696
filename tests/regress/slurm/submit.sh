#!/usr/bin/env bash
# submit.sh check|record SUITE DIR N [pa-regress options...]
# Submits a pa-regress suite to Slurm as a job array of N shards (pa-regress-shard.sbatch) and,
# for check, a merge job that starts when every shard has ended (afterany: shards that find
# regressions exit 1 and must still be merged). DIR must be on a file system all nodes share.
# Prints "ARRAY_JOB_ID [MERGE_JOB_ID]". Extra sbatch options: PA_REGRESS_SBATCH_OPTS (e.g.
# "--partition=render --cpus-per-task=8 --time=30").
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
command="$1"; suite="$(realpath "$2")"; dir="$(realpath -m "$3")"; n="$4"; shift 4
[[ "$command" == check || "$command" == record ]] || { echo "usage: submit.sh check|record SUITE DIR N [options]"; exit 2; }
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
