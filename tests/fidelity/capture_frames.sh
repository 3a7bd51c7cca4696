#!/usr/bin/env bash
# capture_frames.sh OUT_DIR RENDERER MODULE FRAMES [engine args...]
# Plays a demo (CAPTURE_DEMO: OpenArena's demo088-test1 by default, or a .dm_71 file such as
# tests/demos/dm3_rockets.dm_71) as a timedemo in Debian's ioquake3 under xvfb-run and writes
# OUT_DIR/frame_NNNN.tga (uncompressed TGA: stock opengl1 of this engine has no screenshotPNG) at each engine frame number in FRAMES (e.g. "60 120 180"), plus
# OUT_DIR/engine.log.  RENDERER: "pathtracer" (MODULE is our .so) or "opengl1" (MODULE ignored).
# Size: CAPTURE_WIDTH x CAPTURE_HEIGHT (640x360 by default).
#
# Why the frames are the same moment in every run: with `timedemo 1` the client sets the demo
# clock to base + 50 ms * (frames rendered since the first active frame) (ioquake3 cl_cgame.c,
# CL_SetCGameTime), whatever the wall-clock speed, and `wait N` counts command-buffer ticks
# (measured: two per rendered frame here), the same in every run. "Frame N" names tick N.
# Both stock opengl1 and our module read back the frame finished before the screenshot command,
# so the same tick is the same moment (README.md, "How frames are made the same moment").
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/engine_env.sh"
out="$1"; renderer="$2"; module="$3"; frames="$4"; shift 4
pa_capture_demo_ticks "$out" "$renderer" "$module" "${CAPTURE_DEMO:-demo088-test1}" frame "$frames" \
  "${CAPTURE_TIMEOUT:-400}" "$@"
echo "captured $(wc -w <<<"$frames") frames with $renderer into $out"
