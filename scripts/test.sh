#!/usr/bin/env bash
# The one command that runs every test: set-up, build, then ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
# Tests labelled "long" (hours: valgrind soak) run only on request: ctest -L long.
cd build && ctest --output-on-failure -j"$(nproc)" -LE long "$@"
