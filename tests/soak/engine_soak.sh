#!/usr/bin/env bash
# Soak of the real game: Debian's unmodified ioquake3 with our renderer module under xvfb-run,
# PA_SOAK_MAPS (default 20) `map` changes over five OpenArena maps with a `vid_restart` after
# each one (the module is dlclose()d and loaded again every time), then `quit`, under a
# memory checker:
#   engine_soak.sh asan MODULE
#       MODULE comes from a PATHARENA_SANITIZE build made with gcc (tests/soak/README.md);
#       gcc's libasan is preloaded into the engine, LeakSanitizer reports at exit. A shim keeps
#       the module mapped at dlclose so that leak stacks can name its frames.
#   engine_soak.sh plain MODULE
#       no checker: the same 20 map changes and vid_restarts, for crashes and fallbacks only.
#   engine_soak.sh valgrind MODULE
#       any build; valgrind --leak-check=full --keep-debuginfo=yes (the module's frames stay
#       named after dlclose). Slow: Mesa's llvmpipe and the tracer run under valgrind.
# Fails on a crash, a fallback to a stock renderer, a missed map or reload, an ASan/UBSan
# error, or any leak with a frame in our module (valgrind: "definitely lost" blocks; ASan:
# "Direct leak" records). Leaks wholly inside the engine, SDL or Mesa are counted and shown
# but do not fail. Exit 77 (skipped) when the engine, the game data, xvfb-run or the checker
# are missing.
#   PA_SOAK_MAPS    map changes (default 20)
#   PA_SOAK_WAIT    frames waited after each map and each vid_restart (default 60)
#   PA_SOAK_TIMEOUT seconds (default 900 plain, 1200 asan, 7200 valgrind)
#   PA_SOAK_KEEP    folder to copy the engine and checker logs to
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
mode="${1:-}"; module="${2:-}"
[[ "$mode" =~ ^(plain|asan|valgrind)$ ]] && [[ -f "$module" ]] ||
  { echo "usage: $0 plain|asan|valgrind MODULE"; exit 2; }
# shellcheck source=../fidelity/engine_env.sh
source "$here/../fidelity/engine_env.sh"
if ! pa_engine_available; then echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; fi
engine="$PA_ENGINE"
maps=(oa_dm1 aggressor oacmpdm1 q3dm6ish oa_ctf2)
changes="${PA_SOAK_MAPS:-20}"
wait_frames="${PA_SOAK_WAIT:-60}"

work="$(mktemp -d /tmp/pathtracer-soak.XXXXXX)"
trap 'kill "${sampler:-}" 2>/dev/null || true; rm -rf "$work"' EXIT
pa_engine_prepare "$work" "$module"
log="$work/engine.log"
checker_log="$work/checker.log"
wrapper="$work/engine_under_checker.sh"

case "$mode" in
  plain)
    printf '#!/bin/sh\necho $$ > "%s"\nexec "%s" "$@"\n' "$work/engine.pid" "$engine" > "$wrapper"
    timeout_s="${PA_SOAK_TIMEOUT:-900}"
    threads=0
    ;;
  asan)
    libasan="$(gcc -print-file-name=libasan.so)"
    libasan="$(readlink -f "$libasan")"
    needed="$(ldd "$module")"   # (not piped into grep -q: pipefail would see ldd's SIGPIPE)
    if [[ ! -f "$libasan" || "$needed" != *libasan* ]]; then
      echo "skipped: need gcc's libasan and a module built with -fsanitize=address (gcc)"; exit 77
    fi
    cc -shared -fPIC -O2 -o "$work/keep_module_mapped.so" "$here/keep_module_mapped.c" -ldl
    # The engine is not instrumented: only the module's accesses are checked, but every
    # allocation (the engine's too) goes through ASan, so LeakSanitizer sees all of them.
    cat > "$wrapper" <<SH
#!/bin/sh
export LD_PRELOAD="$libasan $work/keep_module_mapped.so"
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:suppressions=$here/asan_engine.supp:log_path=$work/asan:malloc_context_size=30:stack_trace_format='    #%n %p in %f %S <%m>'"
export LSAN_OPTIONS="exitcode=0:report_objects=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=0:log_path=$work/ubsan"
echo \$\$ > "$work/engine.pid"
exec "$engine" "\$@"
SH
    timeout_s="${PA_SOAK_TIMEOUT:-1200}"
    threads=0
    ;;
  valgrind)
    if ! command -v valgrind >/dev/null; then echo "skipped: valgrind not installed"; exit 77; fi
    cat > "$wrapper" <<SH
#!/bin/sh
echo \$\$ > "$work/engine.pid"
exec valgrind --leak-check=full --show-leak-kinds=definite --errors-for-leak-kinds=definite \
  --keep-debuginfo=yes --fullpath-after= --num-callers=30 --error-limit=no --fair-sched=yes \
  --log-file="$checker_log" "$engine" "\$@"
SH
    timeout_s="${PA_SOAK_TIMEOUT:-7200}"
    threads=1   # valgrind runs one thread at a time anyway
    ;;
esac
chmod +x "$wrapper"

cfg="$(pa_engine_cfg "$work" soak)"
{
  for ((i = 0; i < changes; ++i)); do
    echo "map ${maps[i % ${#maps[@]}]}"
    echo "wait $wait_frames"
    echo "vid_restart"
    echo "wait $wait_frames"
  done
  echo "quit"
} > "$cfg"

# The engine's threads, sampled every second (count, then their names): the steady count must
# not climb over the vid_restarts. A thread that lives for a moment around a restart (Mesa's
# shader-cache thread, an audio device reopened) is caught by some samples and not by others,
# so the halves are compared by their median count, not their largest.
(
  while sleep 1; do
    pid="$(cat "$work/engine.pid" 2>/dev/null)" || continue
    tasks=("/proc/$pid/task/"*)
    [[ -e "${tasks[0]}" ]] || continue
    echo "${#tasks[@]} $(cat "/proc/$pid/task/"*/comm 2>/dev/null | tr '\n' ' ')" >> "$work/threads.txt"
  done
) &
sampler=$!
start=$(date +%s)
set +e
PA_ENGINE="$wrapper" LP_NUM_THREADS="$((threads == 1 ? 0 : 2))" \
  pa_engine_run "$work" "$log" "$timeout_s" 200 150 pathtracer \
  +set r_pt_scale 0.1 +set r_pt_preset lightmap +set r_pt_threads "$threads" \
  +set com_maxfps 60 +exec soak.cfg
status=$?
set -e
seconds=$(( $(date +%s) - start ))
kill "$sampler" 2>/dev/null || true
wait "$sampler" 2>/dev/null || true
touch "$work/threads.txt"
median() { sort -n | awk '{ v[NR] = $1 } END { print (NR ? v[int((NR + 1) / 2)] : 0) }'; }
counts="$(cut -d' ' -f1 "$work/threads.txt")"
half=$(( $(grep -c . <<< "$counts" || true) / 2 ))
threads_first=$(head -n "$half" <<< "$counts" | median)
threads_second=$(tail -n +"$((half + 1))" <<< "$counts" | median)
threads_most=$(sort -n <<< "$counts" | tail -n 1)
cat "$work"/asan.* "$work"/ubsan.* > "$checker_log.sanitizers" 2>/dev/null || true
if [[ "$mode" == asan ]]; then mv "$checker_log.sanitizers" "$checker_log"; fi
touch "$checker_log"
if [[ -n "${PA_SOAK_KEEP:-}" ]]; then mkdir -p "$PA_SOAK_KEEP"; cp "$log" "$checker_log" "$PA_SOAK_KEEP/"; fi

# Leak records (blank-line separated blocks), classified by their allocation site: the first
# frame past the allocator, libc, libstdc++ and libtbb. It is ours when it lies in the module or
# in our sources; a leak inside Mesa, SDL or libdbus (even one reached through our calls, such
# as llvmpipe's per-context 112 bytes under a texture upload) is a third-party leak.
ours='renderer_pathtracer|/port/(engine_glue|q3formats|scene_bridge)/|/renderer/(core|bvh|scene)/'
passthrough='vgpreload|libasan|asan_malloc|/libc\.so|libstdc\+\+|libtbb|libgcc_s|: (malloc|calloc|realloc|free|strdup|operator new)'
count_leaks() {   # count_leaks HEADER_REGEX ours|theirs: number of such records (ours: listed on stderr)
  awk -v header="$1" -v ours="$ours" -v pass="$passthrough" -v want="$2" '
    function flush() {
      if (inblock && site == want) { n++; if (want == "ours") printf "%s\n", block > "/dev/stderr" }
      inblock = 0; site = ""; block = ""
    }
    /^(==[0-9]+== *)?$/ { flush(); next }
    $0 ~ header { flush(); inblock = 1 }
    !inblock { next }
    { block = block $0 "\n" }
    site == "" && $0 ~ /^(==[0-9]+==)? *(at 0x|by 0x|#[0-9]+ )/ {
      if ($0 ~ ours) site = "ours"; else if ($0 !~ pass) site = "theirs"
    }
    END { flush(); print n + 0 }' "$checker_log"
}
if [[ "$mode" == valgrind ]]; then header='definitely lost in loss record'; else header='^Direct leak of'; fi
leaks_theirs=$(count_leaks "$header" theirs)
leaks_ours=$(count_leaks "$header" ours)
loads=$(grep -c "pathtracer: loaded maps/" "$log" || true)
banners=$(grep -c "PathArena path tracer renderer" "$log" || true)
echo "engine_soak $mode: $changes map changes + $changes vid_restarts in ${seconds}s, exit $status;" \
     "$loads world loads, $banners module loads; threads: median $threads_first (first half), $threads_second (second half), most $threads_most; leak records: $leaks_ours allocated in our module, $leaks_theirs inside system libraries"

fail() { echo "FAIL: $*"; echo "---- engine log (tail) ----"; tail -n 40 "$log"; echo "---- checker log (head) ----"; head -n 60 "$checker_log"; exit 1; }
[[ $status -eq 0 ]] || fail "engine exited with status $status"
pa_engine_used_renderer "$log" pathtracer || fail "our module was not the renderer (fallback?)"
grep -E -q "Received signal|Segmentation|Sys_Error|ERROR:" "$log" && fail "engine reported a crash or error"
grep -E -q "ERROR: AddressSanitizer|runtime error:" "$checker_log" && fail "sanitizer error"
[[ $banners -ge $((changes + 1)) ]] || fail "the module was loaded $banners times, expected $((changes + 1))"
# A thread leaked per map change or vid_restart (40 of them) raises the second half's median by
# many; one started once partway (a lazily created worker) raises it by one, and its sampling
# decides which half's median shows it.
if [[ $threads_second -gt $((threads_first + 1)) ]]; then
  echo "---- thread samples (count, names) ----"; sort -n "$work/threads.txt" | uniq -c
  fail "threads accumulate: median $threads_first in the first half, $threads_second in the second"
fi
[[ $loads -ge $((2 * changes)) ]] || fail "$loads world loads, expected $((2 * changes)) (each map, then after its vid_restart)"
if [[ "$mode" == valgrind ]]; then
  grep -q "LEAK SUMMARY\|All heap blocks were freed" "$checker_log" || fail "valgrind wrote no leak summary"
  grep -E "definitely lost:|ERROR SUMMARY" "$checker_log" | sed 's/^==[0-9]*== */  valgrind (whole process): /'
fi
[[ $leaks_ours -eq 0 ]] || fail "$leaks_ours leak records allocated in our module (listed above)"
echo "PASS: engine_soak $mode"
