#!/usr/bin/env bash
# The one command that runs every test: set-up, build, then ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
# Tests labelled "long" (hours: valgrind soak) run only on request: ctest -L long. The label
# "subset" marks all_maps_render.subset, whose 10 maps all_maps_render.full renders too.
cd build && ctest --output-on-failure -j"$(nproc)" -LE "long|subset" "$@"
