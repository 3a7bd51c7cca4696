#!/usr/bin/env bash
# scripts/still_view_stability.sh MAP "X Y Z YAW" [N] [-- engine args...]
# Temporal stability of a still view in the real engine: loads MAP (devmap, noclip, no gun, no
# 2D, no view bob) with our module, stands at the view for 40 frames, then takes N (default 8)
# screenshots of consecutive frames and prints the mean absolute frame-to-frame change of
# display luma (0..1; Rec. 709 weights on the sRGB values) over the N - 1 pairs, and the mean
# luma. Engine args after -- (e.g. +set r_pt_preset path +set r_pt_temporal 0).
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tests/fidelity/engine_env.sh"
map="$1"; view="$2"; shift 2
count=8
[[ $# -gt 0 && "$1" != "--" ]] && { count="$1"; shift; }
[[ $# -gt 0 ]] && shift
module="${PA_MODULE:-$root/build/port/engine_glue/renderer_pathtracer_x86_64.so}"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
[[ "$map" =~ ^[A-Za-z0-9_]+$ ]] || { echo "bad map name: $map"; exit 2; }
[[ "$view" =~ ^-?[0-9.]+\ -?[0-9.]+\ -?[0-9.]+\ -?[0-9.]+$ ]] || { echo "bad view '$view' (X Y Z YAW)"; exit 2; }
[[ "$count" =~ ^[0-9]+$ && "$count" -ge 2 ]] || { echo "N must be 2 or more"; exit 2; }
work="$(mktemp -d /tmp/pa-still.XXXXXX)"
trap 'rm -rf "$work"' EXIT
pa_engine_prepare "$work" "$module"
cfg="$(pa_engine_cfg "$work" still)"
printf 'wait 60\nnoclip\nsetviewpos %s\nwait 80\n' "$view" >"$cfg"
# `wait 2` is one rendered frame (two command-buffer ticks per frame: tests/fidelity/capture_frames.sh).
for ((i = 1; i <= count; i++)); do printf 'screenshot still_%02d\nwait 2\n' "$i" >>"$cfg"; done
printf 'wait 5\nquit\n' >>"$cfg"
pa_engine_run "$work" "$work/engine.log" "${STILL_TIMEOUT:-300}" 640 360 pathtracer \
  +set sv_pure 0 +set cg_drawGun 0 +set cg_draw2D 0 +set cg_bobup 0 +set cg_bobpitch 0 \
  +set cg_bobroll 0 +set con_notifytime -1 "$@" +devmap "$map" +exec still.cfg || true
python3 - "$work"/home/baseoa/screenshots/still_*.tga <<'PY'
import struct, sys
def luma(path):
    d = open(path, "rb").read()
    idlen, kind, bpp = d[0], d[2], d[16]
    w, h = struct.unpack("<HH", d[12:16])
    n = bpp // 8
    if kind not in (2, 10) or n not in (3, 4):
        sys.exit(f"{path}: not a 24/32-bit true-colour TGA")
    pos = 18 + idlen
    if kind == 2:
        px = d[pos:pos + w * h * n]
    else:  # run-length encoded
        px = bytearray()
        while len(px) < w * h * n:
            count = (d[pos] & 0x7F) + 1
            if d[pos] & 0x80:
                px += d[pos + 1:pos + 1 + n] * count
                pos += 1 + n
            else:
                px += d[pos + 1:pos + 1 + n * count]
                pos += 1 + n * count
    return [(0.0722 * px[i] + 0.7152 * px[i + 1] + 0.2126 * px[i + 2]) / 255.0 for i in range(0, len(px), n)]
frames = [luma(p) for p in sys.argv[1:]]
if len(frames) < 2:
    sys.exit("fewer than two screenshots were written")
changes = [sum(abs(a - b) for a, b in zip(f, g)) / len(f) for f, g in zip(frames, frames[1:])]
print(f"frames {len(frames)} mean_abs_frame_change {sum(changes) / len(changes):.5f} "
      f"mean_luma {sum(sum(f) / len(f) for f in frames) / len(frames):.4f}")
PY
