#!/usr/bin/env bash
# scripts/engine_bench.sh [options]: speed of each PathArena preset beside the stock opengl1
# renderer, measured in one invocation with Debian's unmodified ioquake3 under xvfb-run over a
# set of demos: for each demo, `timedemo 1` with opengl1 then with each preset, the engine's own
# result line "N frames X seconds Y fps ..." parsed for every run. Prints a table per demo (fps and
# ratio to opengl1), then per preset the geometric mean of the ratios over the demos and the
# worst demo.
#   --demos "a b"     demos to play (default: every tests/demos/*.dm_71, by name without the
#                     extension, then OpenArena's demo088-test1; a path to a .dm_71 file works too)
#   --module PATH     our renderer module (default build/port/engine_glue/renderer_pathtracer_x86_64.so)
#   --size WxH        window size (default 640x360)
#   --messages N      cap: play only the first N messages of each demo (about N frames, 50 ms of game
#                     each; default 200; 0 = whole demos, demo088-test1 alone is 3389 messages, too
#                     long for the traced presets on a small machine)
#   --presets "..."   presets to run after opengl1 (default "lightmap direct path reference"); a
#                     preset may carry cvars of its own: "path:r_pt_temporal=0,r_pt_spp=2"
#   --scale S         r_pt_scale for our module (default: the module's default)
#   --threads N       r_pt_threads (default 0 = all cores)
#   --timeout S       per-run limit in seconds (default 600)
#   --repeat N        play each demo N times with every renderer, in rounds (opengl1, then each
#                     preset, then again), and report each renderer's median fps, the ratios of
#                     the medians and each fps's spread over the rounds (default 1); single runs
#                     move by 5-15% on a shared 2-core machine, opengl1 by more
#   --json FILE       also write the tables as JSON (with every round's fps under "fps_runs")
#   --keep DIR        keep each run's engine log in DIR (DEMO.RENDERER.log; .ROUND.log with --repeat)
# Our module runs with r_pt_stats 1: the per-frame breakdown it prints every 2 s (scene update,
# commit, trace, denoise, resolve, upload, HUD model views, 2D, present, rest of the engine) is
# averaged over the run (over every round with --repeat), printed under each demo's table and
# written to the JSON.
# Exit 77 when the engine, the game data or xvfb-run are missing; 1 when a run fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tests/fidelity/engine_env.sh"

module="$root/build/port/engine_glue/renderer_pathtracer_x86_64.so"
size=640x360; messages=200; presets="lightmap direct path reference"
scale=""; threads=0; timeout_s=600; json=""; keep=""; demos=""; repeat=1
while [[ $# -gt 0 ]]; do
  case "$1" in
    --demos) demos="$2"; shift 2 ;;
    --module) module="$2"; shift 2 ;;
    --size) size="$2"; shift 2 ;;
    --messages) messages="$2"; shift 2 ;;
    --presets) presets="$2"; shift 2 ;;
    --scale) scale="$2"; shift 2 ;;
    --threads) threads="$2"; shift 2 ;;
    --timeout) timeout_s="$2"; shift 2 ;;
    --json) json="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    -h|--help) sed -n '2,30p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "engine_bench: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ "$size" =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "engine_bench: bad --size $size" >&2; exit 2; }
width="${BASH_REMATCH[1]}"; height="${BASH_REMATCH[2]}"
[[ "$messages" =~ ^[0-9]+$ ]] || { echo "engine_bench: bad --messages $messages" >&2; exit 2; }
[[ "$repeat" =~ ^[1-9][0-9]*$ ]] || { echo "engine_bench: bad --repeat $repeat" >&2; exit 2; }
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
[[ -f "$module" ]] || { echo "engine_bench: no module at $module (build the renderer_pathtracer target)" >&2; exit 1; }

if [[ -z "$demos" ]]; then
  for file in "$root"/tests/demos/*.dm_71; do
    [[ -f "$file" ]] && demos+="$(basename "$file" .dm_71) "
  done
  demos+="demo088-test1"
fi

work="$(mktemp -d /tmp/pa-bench.XXXXXX)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/demo"

# Each demo is written to $work/demo/NAME.dm_71, cut to the cap and ended by the end marker.
declare -A played
names=""
cap="$messages"; [[ "$cap" -eq 0 ]] && cap=1000000000
for demo in $demos; do
  source_file=""
  case "$demo" in
    demo088-test1) ;;  # read by pa_demo_truncate from OpenArena's pak6-patch088.pk3
    */*|*.dm_71) source_file="$demo"; demo="$(basename "$demo" .dm_71)" ;;
    *) source_file="$root/tests/demos/$demo.dm_71" ;;
  esac
  [[ -z "$source_file" || -f "$source_file" ]] || { echo "engine_bench: no demo $source_file" >&2; exit 2; }
  played[$demo]="$(pa_demo_truncate "$work/demo/$demo.dm_71" "$cap" "$source_file")"
  names+="$demo "
done

# Results keyed "DEMO:RENDERER"; "-" where a run failed. With --repeat, fps is the median over the
# rounds that worked, frames and seconds those of the round closest to it, runs every round's fps.
declare -A fps frames seconds breakdown runs round_frames round_seconds
# The r_pt_stats lines of a log averaged field by field: "name=value ..." (empty without any).
average_stats() {  # empty for a log without stats lines (opengl1's), not a failure
  { grep -a '^pathtracer: stats ' "$1" || true; } | awk '{
      for (i = 4; i <= NF; i++) { split($i, kv, "="); if (!(kv[1] in sum)) order[++n] = kv[1]; sum[kv[1]] += kv[2] }
      lines++
    }
    END { for (i = 1; i <= n; i++) printf "%s%s=%.2f", (i > 1 ? " " : ""), order[i], sum[order[i]] / lines }'
}
stats_file() { echo "$work/stats.$1.${2//[^A-Za-z0-9_.=-]/_}"; }   # stats_file DEMO NAME: its runs' stats lines
run_one() {  # run_one DEMO NAME ROUND RENDERER [engine args...]
  local demo="$1" name="$2" round="$3" renderer="$4"; shift 4
  local key="$demo:$name" dir="$work/run" log="$work/run.log"
  rm -rf "$dir"
  if [[ "$renderer" == pathtracer ]]; then pa_engine_prepare "$dir" "$module"; else pa_engine_prepare "$dir"; fi
  mkdir -p "$dir/home/baseoa/demos"
  cp "$work/demo/$demo.dm_71" "$dir/home/baseoa/demos/pa_bench.dm_71"
  echo "engine_bench: running $demo with $name$([[ $repeat -gt 1 ]] && echo " (round $round of $repeat)") ..." >&2
  local status=0
  pa_engine_run "$dir" "$log" "$timeout_s" "$width" "$height" "$renderer" \
    +set timedemo 1 +set com_maxfps 0 +set nextdemo quit "$@" +demo pa_bench || status=$?
  if [[ -n "$keep" ]]; then
    mkdir -p "$keep"
    if [[ $repeat -gt 1 ]]; then cp "$log" "$keep/$demo.$name.$round.log"; else cp "$log" "$keep/$demo.$name.log"; fi
  fi
  local line
  line="$(grep -a -E '^[0-9]+ frames [0-9.]+ seconds [0-9.]+ fps' "$log" | tail -n 1 || true)"
  if [[ -z "$line" ]] || ! pa_engine_used_renderer "$log" "$renderer"; then
    echo "engine_bench: $demo with $name failed (status $status); log tail:" >&2
    grep -a -v GL_EXTENSIONS "$log" | tail -n 15 >&2
    runs[$key]+="- "
    return 1
  fi
  local run_frames run_seconds run_fps
  read -r run_frames _ run_seconds _ run_fps _ <<<"$line"
  runs[$key]+="$run_fps "
  round_frames[$key:$round]="$run_frames"; round_seconds[$key:$round]="$run_seconds"
  { grep -a '^pathtracer: stats ' "$log" || true; } >>"$(stats_file "$demo" "$name")"
}
# settle DEMO NAME: the median fps over the rounds that worked, the frames and seconds of the
# round whose fps is nearest to it, and the breakdown over every round's stats lines.
settle() {
  local key="$1:$2" median best
  # One round: the engine's own figure; more: the median (the mean of the middle two). Then the
  # round (1-based, "-" rounds counted) whose fps is nearest to it; "- 0" when every round failed.
  read -r median best < <(awk '{
      for (i = 1; i <= NF; i++) if ($i != "-") { v[++n] = $i; round[n] = i }
      if (n == 0) { print "- 0"; exit }
      for (i = 1; i <= n; i++) s[i] = v[i]
      for (i = 2; i <= n; i++) for (j = i; j > 1 && s[j - 1] > s[j]; j--) { t = s[j]; s[j] = s[j - 1]; s[j - 1] = t }
      m = n % 2 ? s[(n + 1) / 2] : (s[n / 2] + s[n / 2 + 1]) / 2
      best = 1
      for (i = 2; i <= n; i++) if ((v[i] - m) ^ 2 < (v[best] - m) ^ 2) best = i
      if (n == 1) printf "%s %d\n", v[1], round[1]; else printf "%.1f %d\n", m, round[best]
    }' <<<"${runs[$key]:-}")
  fps[$key]="$median"
  frames[$key]="${round_frames[$key:$best]:--}"
  seconds[$key]="${round_seconds[$key:$best]:--}"
  local stats
  stats="$(stats_file "$1" "$2")"
  breakdown[$key]="$([[ -f "$stats" ]] && average_stats "$stats" || true)"
}

failed=0
pt_args=(+set r_pt_threads "$threads" +set r_pt_stats 1)
[[ -n "$scale" ]] && pt_args+=(+set r_pt_scale "$scale")
for demo in $names; do
  for ((round = 1; round <= repeat; round++)); do
    run_one "$demo" opengl1 "$round" opengl1 || failed=1
    for preset in $presets; do
      extra=()
      if [[ "$preset" == *:* ]]; then
        IFS=',' read -ra settings <<<"${preset#*:}"
        for setting in "${settings[@]}"; do extra+=(+set "${setting%%=*}" "${setting#*=}"); done
      fi
      run_one "$demo" "$preset" "$round" pathtracer "${pt_args[@]}" +set r_pt_preset "${preset%%:*}" "${extra[@]}" || failed=1
    done
  done
  for name in opengl1 $presets; do settle "$demo" "$name"; done
done

ratio() {  # ratio DEMO NAME -> fps of NAME / fps of opengl1 on DEMO, or "-"
  local a="${fps[$1:$2]}" b="${fps[$1:opengl1]}"
  [[ "$a" != - && "$b" != - ]] && awk -v a="$a" -v b="$b" 'BEGIN{printf "%.3f", a/b}' || echo "-"
}
# summary PRESET -> "GEOMEAN WORST_DEMO WORST_RATIO COUNT" over the demos where both runs worked
summary() {
  local demo r list=""
  for demo in $names; do
    r="$(ratio "$demo" "$1")"; [[ "$r" != - ]] && list+="$demo $r"$'\n'
  done
  awk 'NF == 2 { n++; s += log($2); if (n == 1 || $2 < w) { w = $2; wd = $1 } }
       END { if (n) printf "%.3f %s %.3f %d\n", exp(s / n), wd, w, n; else print "- - - 0" }' <<<"$list"
}

load="$(cut -d' ' -f1-3 /proc/loadavg)"
machine="$("$root/scripts/machine.sh")"
echo "$machine"
echo "${width}x${height}, timedemo 1, messages cap ${messages} (0 = whole demos), $(nproc) cores, load $load$([[ $repeat -gt 1 ]] && echo ", $repeat rounds: median fps, ratios of the medians")"
echo "pathtracer: r_pt_scale ${scale:-default} r_pt_threads $threads, other cvars at their defaults"
for demo in $names; do
  echo
  echo "$demo: ${played[$demo]} messages"
  printf '%-10s %8s %9s %9s %10s%s\n' renderer frames seconds fps vs_opengl1 "$([[ $repeat -gt 1 ]] && echo "  fps of each round")"
  for name in opengl1 $presets; do
    printf '%-10s %8s %9s %9s %10s%s\n' "$name" "${frames[$demo:$name]}" "${seconds[$demo:$name]}" \
      "${fps[$demo:$name]}" "$(ratio "$demo" "$name")" "$([[ $repeat -gt 1 ]] && echo "  ${runs[$demo:$name]:-}")"
  done
  for name in $presets; do
    [[ -n "${breakdown[$demo:$name]:-}" ]] && echo "  $name per frame (r_pt_stats means): ${breakdown[$demo:$name]}"
  done
done
echo
echo "over $(wc -w <<<"$names") demos: ratio to opengl1"
printf '%-10s %8s %-16s %8s %6s\n' preset geomean worst_demo worst demos
for preset in $presets; do
  read -r geomean worst_demo worst count <<<"$(summary "$preset")"
  printf '%-10s %8s %-16s %8s %6s\n' "$preset" "$geomean" "$worst_demo" "$worst" "$count"
done

if [[ -n "$json" ]]; then
  q() { [[ "$1" == - ]] && echo null || echo "$1"; }
  {
    printf '{"machine": "%s", "messages_cap": %d, "width": %d, "height": %d, "cores": %d, "load": "%s", "rounds": %d, "demos": [' \
      "${machine//\"/}" "$messages" "$width" "$height" "$(nproc)" "$load" "$repeat"
    sep=""
    for demo in $names; do
      printf '%s{"demo": "%s", "messages": %d, "runs": [' "$sep" "$demo" "${played[$demo]}"
      rsep=""
      for name in opengl1 $presets; do
        # The breakdown as a JSON object of numbers (null for opengl1 and failed runs).
        parts="null"
        [[ -n "${breakdown[$demo:$name]:-}" ]] &&
          parts="{$(tr ' ' '\n' <<<"${breakdown[$demo:$name]}" | awk -F= '{printf "%s\"%s\": %s", (NR > 1 ? ", " : ""), $1, $2}')}"
        each="$(for f in ${runs[$demo:$name]:-}; do q "$f"; done | paste -sd, -)"
        printf '%s{"renderer": "%s", "frames": %s, "seconds": %s, "fps": %s, "fps_runs": [%s], "ratio_to_opengl1": %s, "frame_breakdown": %s}' \
          "$rsep" "$name" "$(q "${frames[$demo:$name]}")" "$(q "${seconds[$demo:$name]}")" \
          "$(q "${fps[$demo:$name]}")" "${each//,/, }" "$(q "$(ratio "$demo" "$name")")" "$parts"
        rsep=", "
      done
      printf ']}'
      sep=", "
    done
    printf '], "presets": ['
    sep=""
    for preset in $presets; do
      read -r geomean worst_demo worst count <<<"$(summary "$preset")"
      [[ "$worst_demo" == - ]] && worst_demo=null || worst_demo="\"$worst_demo\""
      printf '%s{"preset": "%s", "geomean_ratio": %s, "worst_demo": %s, "worst_ratio": %s, "demos": %d}' \
        "$sep" "$preset" "$(q "$geomean")" "$worst_demo" "$(q "$worst")" "$count"
      sep=", "
    done
    printf ']}\n'
  } >"$json"
fi
exit $failed
