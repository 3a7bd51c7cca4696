#!/usr/bin/env bash
# scripts/engine_bench.sh [options]: speed of each PathArena preset beside the stock opengl1
# renderer, measured in one invocation with Debian's unmodified ioquake3 under xvfb-run:
# `timedemo 1` + OpenArena's demo088-test1, the engine's own result line
# "N frames X seconds Y fps ..." parsed for every run.
#   --module PATH     our renderer module (default build/port/engine_glue/renderer_pathtracer_x86_64.so)
#   --size WxH        window size (default 640x360)
#   --messages N      cap: play only the first N demo messages (about N frames, 50 ms of game each;
#                     default 200; 0 = the full demo, 3389 messages, too long for the traced presets
#                     on a small machine)
#   --presets "..."   presets to run after opengl1 (default "lightmap direct path reference")
#   --scale S         r_pt_scale for our module (default: the module's default)
#   --threads N       r_pt_threads (default 0 = all cores)
#   --timeout S       per-run limit in seconds (default 600)
#   --json FILE       also write the table as JSON
#   --keep DIR        keep each run's engine log in DIR
# Exit 77 when the engine, the game data or xvfb-run are missing; 1 when a run fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tests/fidelity/engine_env.sh"

module="$root/build/port/engine_glue/renderer_pathtracer_x86_64.so"
size=640x360; messages=200; presets="lightmap direct path reference"
scale=""; threads=0; timeout_s=600; json=""; keep=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --module) module="$2"; shift 2 ;;
    --size) size="$2"; shift 2 ;;
    --messages) messages="$2"; shift 2 ;;
    --presets) presets="$2"; shift 2 ;;
    --scale) scale="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --timeout) timeout_s="$2"; shift 2 ;;
    --json) json="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    -h|--help) sed -n '2,20p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "engine_bench: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ "$size" =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "engine_bench: bad --size $size" >&2; exit 2; }
width="${BASH_REMATCH[1]}"; height="${BASH_REMATCH[2]}"
[[ "$messages" =~ ^[0-9]+$ ]] || { echo "engine_bench: bad --messages $messages" >&2; exit 2; }
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
[[ -f "$module" ]] || { echo "engine_bench: no module at $module (build the renderer_pathtracer target)" >&2; exit 1; }

work="$(mktemp -d /tmp/pa-bench.XXXXXX)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/demo"
if [[ "$messages" -gt 0 ]]; then
  played="$(pa_demo_truncate "$work/demo/pa_bench.dm_71" "$messages")"
else
  played="full"; pa_demo_truncate "$work/demo/pa_bench.dm_71" 1000000 >/dev/null
fi

declare -A fps frames seconds
run_one() {  # run_one NAME RENDERER [engine args...]
  local name="$1" renderer="$2"; shift 2
  local dir="$work/$name" log="$work/$name.log"
  if [[ "$renderer" == pathtracer ]]; then pa_engine_prepare "$dir" "$module"; else pa_engine_prepare "$dir"; fi
  mkdir -p "$dir/home/baseoa/demos"
  cp "$work/demo/pa_bench.dm_71" "$dir/home/baseoa/demos/"
  echo "engine_bench: running $name ..." >&2
  local status=0
  pa_engine_run "$dir" "$log" "$timeout_s" "$width" "$height" "$renderer" \
    +set timedemo 1 +set com_maxfps 0 +set nextdemo quit "$@" +demo pa_bench || status=$?
  [[ -n "$keep" ]] && { mkdir -p "$keep"; cp "$log" "$keep/$name.log"; }
  local line
  line="$(grep -a -E '^[0-9]+ frames [0-9.]+ seconds [0-9.]+ fps' "$log" | tail -n 1 || true)"
  if [[ -z "$line" ]] || ! pa_engine_used_renderer "$log" "$renderer"; then
    echo "engine_bench: $name failed (status $status); log tail:" >&2
    grep -a -v GL_EXTENSIONS "$log" | tail -n 15 >&2
    fps[$name]="-"; frames[$name]="-"; seconds[$name]="-"
    return 1
  fi
  read -r frames[$name] _ seconds[$name] _ fps[$name] _ <<<"$line"
}

failed=0
run_one opengl1 opengl1 || failed=1
pt_args=(+set r_pt_threads "$threads")
[[ -n "$scale" ]] && pt_args+=(+set r_pt_scale "$scale")
for preset in $presets; do
  run_one "$preset" pathtracer "${pt_args[@]}" +set r_pt_preset "$preset" || failed=1
done

ratio() { [[ "${fps[$1]}" != - && "${fps[opengl1]}" != - ]] && awk -v a="${fps[$1]}" -v b="${fps[opengl1]}" 'BEGIN{printf "%.3f", a/b}' || echo "-"; }
echo "demo088-test1, first $played messages, ${width}x${height}, timedemo 1, $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "pathtracer: r_pt_scale ${scale:-default} r_pt_threads $threads, other cvars at their defaults"
printf '%-10s %8s %9s %9s %10s\n' renderer frames seconds fps vs_opengl1
for name in opengl1 $presets; do
  printf '%-10s %8s %9s %9s %10s\n' "$name" "${frames[$name]}" "${seconds[$name]}" "${fps[$name]}" "$(ratio "$name")"
done
if [[ -n "$json" ]]; then
  {
    printf '{"demo": "demo088-test1", "messages": "%s", "width": %d, "height": %d, "cores": %d, "load": "%s", "runs": [' \
      "$played" "$width" "$height" "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)"
    sep=""
    for name in opengl1 $presets; do
      q() { [[ "$1" == - ]] && echo null || echo "$1"; }
      r="$(ratio "$name")"
      printf '%s{"renderer": "%s", "frames": %s, "seconds": %s, "fps": %s, "ratio_to_opengl1": %s}' "$sep" "$name" \
        "$(q "${frames[$name]}")" "$(q "${seconds[$name]}")" "$(q "${fps[$name]}")" "$(q "$r")"
      sep=", "
    done
    printf ']}\n'
  } >"$json"
fi
exit $failed
