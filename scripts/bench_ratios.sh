#!/usr/bin/env bash
# scripts/bench_ratios.sh [--bench PATH] [--runs N] [-- extra bench arguments]: the BVH's speed
# against Embree on the four standard scenes (soup:10000, soup:100000, thin:100000, the oa_dm1
# map), one line per scene and run with the ours / Embree ratios (incoherent, shadow, primary
# rays), as docs/performance.md quotes them. Runs alternate scenes, so several runs spread a
# load spike over all of them; read medians.
#   --bench PATH   bench binary (default build/renderer/bench/bench); copy binaries aside to A/B
#   --runs N       repetitions of the four scenes (default 1)
# Anything after -- goes to every bench call (e.g. -- --embree-robust, -- --bins 16).
# oa_dm1 is converted to out/oa_dm1.glb on first use (needs the openarena-data package).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bench="$root/build/renderer/bench/bench"
runs=1
extra=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --bench) bench="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) echo "bench_ratios: unknown argument $1" >&2; exit 2 ;;
  esac
done
[[ -x "$bench" ]] || { echo "bench_ratios: no bench at $bench (build the bench target)" >&2; exit 1; }

map="$root/out/oa_dm1.glb"
if [[ ! -f "$map" ]]; then
  converter="$root/build/assets_converter/assets_converter"
  [[ -x "$converter" ]] || { echo "bench_ratios: $map missing and no converter to make it" >&2; exit 1; }
  "$converter" --game /usr/share/games/openarena/baseoa --map oa_dm1 -o "$root/out" > /dev/null
fi

for ((run = 1; run <= runs; ++run)); do
  for scene in "--synthetic soup:10000" "--synthetic soup:100000" "--synthetic thin:100000" "--scene $map"; do
    # shellcheck disable=SC2086  # the scene is two words on purpose
    "$bench" $scene --threads 1 --reps 5 --json --no-frames --rays 262144 "${extra[@]}" | python3 -c '
import json, sys
d = json.load(sys.stdin)
print("run %s  %-14s incoherent %.3f  shadow %.3f  primary %.3f  (Mrays/s ours/Embree %.2f/%.2f, %.2f/%.2f, %.2f/%.2f)  build %.3f" % (
    sys.argv[1], d["scene"][-14:], d["incoherent_ratio"], d["shadow_ratio"], d["primary_ratio"],
    d["mrays_incoherent_ours"], d["mrays_incoherent_embree"], d["mrays_shadow_ours"], d["mrays_shadow_embree"],
    d["mrays_primary_ours"], d["mrays_primary_embree"], d["build_ratio"]))' "$run"
  done
done
