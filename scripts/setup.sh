#!/usr/bin/env bash
# Installs every Debian package PathArena needs to build, test and play. Idempotent.
set -euo pipefail
PACKAGES=(
  build-essential cmake ninja-build pkg-config clang libclang-rt-14-dev
  libembree-dev libtbb-dev libglm-dev libsdl2-dev libgl-dev libphysfs-dev
  libtinygltf-dev nlohmann-json3-dev libstb-dev libtinyexr-dev libjpeg-dev
  libgtest-dev libgmock-dev npm
  xvfb xauth libgl1-mesa-dri mesa-utils imagemagick fontconfig fonts-dejavu-core gnuplot-nox
  ioquake3 openarena openarena-data openarena-oacmp1
  slurm-wlm munge
)
missing=()
for p in "${PACKAGES[@]}"; do
  # npm also ships inside other nodejs builds (NodeSource's), which conflict with Debian's npm.
  if [ "$p" = npm ] && command -v npm >/dev/null 2>&1; then continue; fi
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
echo "setup: all packages present"

# Khronos glTF validator for the converter's tests (npm registry; pinned by package-lock.json).
# Without it the validation tests fail (they never skip).
validator_dir="$(cd "$(dirname "$0")/.." && pwd)/assets_converter/tests/gltf_validator"
if [ ! -d "$validator_dir/node_modules/gltf-validator" ]; then
  echo "setup: installing gltf-validator (npm ci)"
  npm ci --prefix "$validator_dir" --no-audit --no-fund --loglevel=error ||
    echo "setup: WARNING: gltf-validator install failed (npm registry unreachable?); the glTF validation tests will fail"
fi
