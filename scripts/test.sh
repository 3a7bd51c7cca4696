#!/usr/bin/env bash
# The one command that runs every test: set-up, build, then ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
cd build && ctest --output-on-failure -j"$(nproc)" "$@"
