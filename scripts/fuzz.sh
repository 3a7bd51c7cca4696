#!/usr/bin/env bash
# libFuzzer harnesses under ASan/UBSan (clang): build, seed corpora, timed runs. See
# port/q3formats/FUZZING.md. Used by the CTests labelled "fuzz" and by developers.
#
#   scripts/fuzz.sh build        configure + build build-fuzz (clang-14), check the committed seeds
#   scripts/fuzz.sh seeds        regenerate the committed seed corpora (fuzz/seeds/ beside each harness)
#   scripts/fuzz.sh run NAME     run one harness for PA_FUZZ_SECONDS (default 30) from its seeds
#   scripts/fuzz.sh all          build, then run every harness, two at a time
#   scripts/fuzz.sh list         the harness names
#
# Environment: PA_FUZZ_SECONDS (run time per harness), PA_FUZZ_DIR (build tree, default
# build-fuzz), PA_FUZZ_JOBS (parallel harnesses for "all", default 2), PA_FUZZ_NICE (default 10).
# A run fails (exit 1) on any crash, sanitizer report (ASan, UBSan, leak), timeout or OOM; the
# input is kept as $PA_FUZZ_DIR/fuzz-artifacts/NAME/crash-* (or leak-*, timeout-*, oom-*); an
# input libFuzzer reports as slow (>= 10 s) fails the run only if it is as slow again alone.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${PA_FUZZ_DIR:-$root/build-fuzz}
seconds=${PA_FUZZ_SECONDS:-30}
niceness=${PA_FUZZ_NICE:-10}

# name | binary (in the build tree) | seed folder (committed, in the source tree; "build:" = made
# by "build" in the build tree: the BSP seeds are 140 KB) | max input length
HARNESSES=(
  "bsp|port/q3formats/bsp/fuzz/fuzz_bsp|build:seeds/bsp|262144"
  "shader|port/q3formats/shader/fuzz/q3_fuzz_shader_script|port/q3formats/shader/fuzz/seeds|16384"
  "md3|port/q3formats/model/fuzz/q3_fuzz_md3|port/q3formats/model/fuzz/seeds/md3|65536"
  "skin|port/q3formats/model/fuzz/q3_fuzz_skin|port/q3formats/model/fuzz/seeds/skin|4096"
  "image|port/q3formats/image/fuzz/q3_fuzz_image|port/q3formats/image/fuzz/seeds|65536"
  "pk3|port/q3formats/vfs/fuzz/q3_fuzz_pk3|port/q3formats/vfs/fuzz/seeds|65536"
  "gltf|renderer/gltf_io/fuzz/pa_fuzz_gltf|renderer/gltf_io/fuzz/seeds|65536"
)
TARGETS=(fuzz_bsp make_bsp_seeds q3_fuzz_shader_script q3_fuzz_shader_seeds q3_fuzz_md3 q3_fuzz_skin
         q3_fuzz_model_seeds q3_fuzz_image q3_fuzz_image_seeds q3_fuzz_pk3 q3_fuzz_pk3_seeds
         pa_fuzz_gltf pa_fuzz_gltf_seeds)

die() { echo "fuzz: $*" >&2; exit 1; }

field() {  # field NAME INDEX
  local h
  for h in "${HARNESSES[@]}"; do
    IFS='|' read -r -a f <<<"$h"
    if [ "${f[0]}" = "$1" ]; then echo "${f[$2]}"; return; fi
  done
  die "unknown harness '$1' (known: $(list | tr '\n' ' '))"
}

list() { local h; for h in "${HARNESSES[@]}"; do echo "${h%%|*}"; done; }

# Writes every seed corpus under $1 (same layout as the source tree).
generate_seeds() {
  local out=$1
  rm -rf "$out"
  "$dir/port/q3formats/shader/fuzz/q3_fuzz_shader_seeds" "$out/port/q3formats/shader/fuzz/seeds" >/dev/null
  "$dir/port/q3formats/model/fuzz/q3_fuzz_model_seeds" "$out/port/q3formats/model/fuzz/seeds/md3" \
    "$out/port/q3formats/model/fuzz/seeds/skin" >/dev/null
  "$dir/port/q3formats/image/fuzz/q3_fuzz_image_seeds" "$out/port/q3formats/image/fuzz/seeds" >/dev/null
  "$dir/port/q3formats/vfs/fuzz/q3_fuzz_pk3_seeds" "$out/port/q3formats/vfs/fuzz/seeds" >/dev/null
  "$dir/renderer/gltf_io/fuzz/pa_fuzz_gltf_seeds" "$out/renderer/gltf_io/fuzz/seeds" >/dev/null
}

# The committed seed folders.
seed_dirs() { local h; for h in "${HARNESSES[@]}"; do IFS='|' read -r -a f <<<"$h"; [[ ${f[2]} == build:* ]] || echo "${f[2]}"; done; }

build() {
  command -v clang++-14 >/dev/null || die "clang++-14 is missing: run scripts/setup.sh"
  find /usr/lib/llvm-14/lib/clang -name 'libclang_rt.fuzzer-x86_64.a' 2>/dev/null | grep -q . ||
    die "libFuzzer (libclang-rt-14-dev) is missing: run scripts/setup.sh"
  CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPATHARENA_FUZZ=ON -DPATHARENA_TESTS=OFF -DPATHARENA_BENCH=OFF >/dev/null
  nice -n "$niceness" cmake --build "$dir" -j"$(nproc)" --target "${TARGETS[@]}"
  # The committed seeds must be what the generators write (regenerate: scripts/fuzz.sh seeds).
  generate_seeds "$dir/seeds-check"
  local d
  for d in $(seed_dirs | sort -u); do
    diff -r "$root/$d" "$dir/seeds-check/$d" >/dev/null ||
      die "committed seeds in $d differ from their generator's output: run scripts/fuzz.sh seeds and commit"
  done
  rm -rf "$dir/seeds/bsp"
  "$dir/port/q3formats/bsp/fuzz/make_bsp_seeds" "$dir/seeds/bsp" >/dev/null
  echo "fuzz: build and seeds OK"
}

run() {
  local name=$1 binary seeds maxlen
  binary="$dir/$(field "$name" 1)"
  seeds=$(field "$name" 2)
  if [[ $seeds == build:* ]]; then seeds="$dir/${seeds#build:}"; else seeds="$root/$seeds"; fi
  maxlen=$(field "$name" 3)
  [ -x "$binary" ] || die "$binary is not built: run scripts/fuzz.sh build"
  [ -d "$seeds" ] || die "no seed corpus at $seeds"
  local corpus="$dir/fuzz-corpus/$name" artifacts="$dir/fuzz-artifacts/$name" log="$dir/fuzz-logs/$name.log"
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  rm -f "$artifacts"/*
  echo "fuzz: $name for ${seconds} s (corpus $corpus, log $log)"
  local rc=0 start=$SECONDS
  # New inputs go to the corpus folder (the first one); the committed seeds are only read.
  # The outer timeout is a last resort against a hang that libFuzzer itself cannot stop.
  timeout -k 10 $((seconds + 300)) nice -n "$niceness" "$binary" "$corpus" "$seeds" \
    -max_total_time="$seconds" -max_len="$maxlen" -timeout=60 -rss_limit_mb=2560 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" >"$log" 2>&1 || rc=$?
  local wall=$((SECONDS - start))
  grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | tail -1 || true
  grep -E '^stat::' "$log" || true
  # libFuzzer keeps an input that took >= 10 s as slow-unit-*; on a loaded machine a niced run
  # can stall that long on any input. Such an input is run again alone, and counts only if it
  # is still slow.
  local unit again
  for unit in "$artifacts"/slow-unit-*; do
    [ -f "$unit" ] || continue
    again=$SECONDS
    timeout 120 "$binary" "$unit" >/dev/null 2>&1 || true
    again=$((SECONDS - again))
    if [ "$again" -lt 10 ]; then
      echo "fuzz: $name: $(basename "$unit") took $again s run again alone (slow only under load): not a finding"
      rm -f "$unit"
    fi
  done
  local findings
  findings=$(find "$artifacts" -type f | wc -l)
  if [ "$rc" -ne 0 ] || [ "$findings" -ne 0 ] || grep -qE 'runtime error:|ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)' "$log"; then
    echo "fuzz: $name FAILED (exit $rc, ${wall} s); report:"
    grep -E -A 30 'runtime error:|ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)' "$log" | head -60 || tail -40 "$log"
    ls -l "$artifacts"
    echo "fuzz: reproduce with $binary $artifacts/<file>"
    return 1
  fi
  echo "fuzz: $name OK (${wall} s, corpus $(find "$corpus" -type f | wc -l) inputs)"
}

case "${1:-}" in
  build) build ;;
  seeds)
    [ -x "$dir/renderer/gltf_io/fuzz/pa_fuzz_gltf_seeds" ] ||
      die "build the generators first: scripts/fuzz.sh build (its seed check may fail; that is expected here)"
    generate_seeds "$dir/seeds-new"
    for d in $(seed_dirs | sort -u); do
      rm -rf "${root:?}/$d"
      mkdir -p "$(dirname "$root/$d")"
      cp -r "$dir/seeds-new/$d" "$root/$d"
    done
    echo "fuzz: seeds written" ;;
  run) [ $# -eq 2 ] || die "usage: scripts/fuzz.sh run NAME"; run "$2" ;;
  all)
    build
    jobs=${PA_FUZZ_JOBS:-2} failed=0
    names=$(list)
    # xargs runs PA_FUZZ_JOBS harnesses at a time; each prints its own stats when it ends.
    echo "$names" | xargs -P "$jobs" -I{} "$0" run {} || failed=1
    exit $failed ;;
  list) list ;;
  *) sed -n '2,15p' "$0"; exit 2 ;;
esac
