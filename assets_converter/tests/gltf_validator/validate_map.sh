#!/usr/bin/env bash
# CTest driver: converts one real map with assets_converter and validates the .glb with the
# Khronos glTF-Validator. Exit 1 when node or the validator package is missing (scripts/setup.sh
# installs both), when conversion fails or when the validator reports errors; 77 (CTest
# "skipped") only when the game data folder is missing.
# usage: validate_map.sh CONVERTER GAME_DIR MAP OUT_DIR
set -uo pipefail
converter=$1 game=$2 map=$3 out=$4
here=$(cd "$(dirname "$0")" && pwd)

if ! command -v node >/dev/null; then
  echo "FAIL: node is not installed: run scripts/setup.sh (Debian package npm)"; exit 1
fi
if [ ! -d "$here/node_modules/gltf-validator" ]; then
  # One attempt at a local install from package-lock.json (needs the npm registry).
  if ! command -v npm >/dev/null || ! (cd "$here" && npm ci --no-audit --no-fund >/dev/null 2>&1); then
    echo "FAIL: the Khronos glTF validator is not installed: run scripts/setup.sh (npm ci in $here)"; exit 1
  fi
fi
if [ ! -d "$game" ]; then echo "SKIP: no game data at $game"; exit 77; fi

mkdir -p "$out"
"$converter" --game "$game" --map "$map" -o "$out" || exit 1
node "$here/validate.js" "$out/$(basename "${map%.bsp}").glb"
