#!/usr/bin/env bash
# Builds the renderer module and the soak test with AddressSanitizer + UndefinedBehaviorSanitizer
# + LeakSanitizer (CMake option PATHARENA_SANITIZE, gcc) in a separate build folder, then runs
#   1. engine_glue_soak: the module driven by the fake engine, 20 map loads + vid_restarts;
#      any ASan/UBSan error or LSan leak report fails it (suppressions: tests/soak/lsan.supp);
#   2. engine_soak_asan: the real Debian ioquake3 with the sanitized module (libasan preloaded),
#      20 map changes + 20 vid_restarts; any leak with a frame in our module fails it.
#   tests/soak/sanitized_soak.sh [BUILD_DIR]      (default: build-asan at the repository root)
# Takes a full build of the tracer the first time (ccache makes later ones quick).
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
build="${1:-$root/build-asan}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPATHARENA_SANITIZE=ON \
  -DPATHARENA_BENCH=OFF -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache >/dev/null
cmake --build "$build" --target renderer_pathtracer engine_glue_soak_tests -j"${PA_JOBS:-2}"
ctest --test-dir "$build" -R '^engine_(glue_)?soak' --output-on-failure
