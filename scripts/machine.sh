#!/usr/bin/env bash
# scripts/machine.sh: one line naming this machine for a benchmark's header: the CPU's model name,
# family and model (Zen 4 is family 25, Zen 5 family 26), its cores, and the Mesa build whose
# llvmpipe draws opengl1. Ratios to opengl1 and to Embree move by up to 2x between machines
# (docs/performance.md, "Presets on a Zen 4 against opengl1"): every figure names its machine.
set -euo pipefail
field() { awk -F': *' -v k="$1" '$1 ~ "^" k "[ \t]*$" { print $2; exit }' /proc/cpuinfo; }
mesa="$(dpkg-query -W -f='${Version}' libgl1-mesa-dri 2>/dev/null || true)"
echo "cpu: $(field 'model name') (family $(field 'cpu family'), model $(field 'model')), $(nproc) cores;" \
  "mesa ${mesa:-unknown}"
