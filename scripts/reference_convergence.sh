#!/usr/bin/env bash
# scripts/reference_convergence.sh MAP "X Y Z YAW" [OUT_DIR] [-- engine args...]
# How far the `reference` preset gets while the player stands still, in the real engine: loads MAP
# (devmap, noclip, gun and 2D on, no view bob) with our module at 640x360, stands at the view and
# takes a screenshot every STEP frames (default 10) up to MAX frames (default 120), printing how
# many frames had accumulated every 2 s (r_pt_stats' period). Then, in the same game state:
#   - `equal_spp`: r_pt_spp set to the frames accumulated at the screenshot nearest SECONDS
#     (default 10, even), one frame: what an offline render of as many samples gives;
#   - `converged`: r_pt_spp 64 for REF_FRAMES frames (default 16, so 1024 spp).
# Prints PSNR / SSIM (pa-imgcompare) of the SECONDS screenshot and of equal_spp against converged.
# Accumulation loses nothing in play when the two agree. Slow: `converged` takes minutes.
# Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tests/fidelity/engine_env.sh"
map="$1"; view="$2"; shift 2
out="$(mktemp -d /tmp/pa-reference.XXXXXX)"
[[ $# -gt 0 && "$1" != "--" ]] && { out="$1"; shift; }
[[ $# -gt 0 ]] && shift
module="${PA_MODULE:-$root/build/port/engine_glue/renderer_pathtracer_x86_64.so}"
compare="${PA_IMGCOMPARE:-$root/build/tests/fidelity/pa-imgcompare}"
step="${STEP:-10}"; max="${MAX:-120}"; seconds="${SECONDS_STILL:-10}"; ref_frames="${REF_FRAMES:-16}"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
[[ "$map" =~ ^[A-Za-z0-9_]+$ ]] || { echo "bad map name: $map"; exit 2; }
[[ "$view" =~ ^-?[0-9.]+\ -?[0-9.]+\ -?[0-9.]+\ -?[0-9.]+$ ]] || { echo "bad view '$view' (X Y Z YAW)"; exit 2; }
[[ -x "$compare" ]] || { echo "missing $compare (build the tree first)"; exit 2; }
mkdir -p "$out"
work="$(mktemp -d /tmp/pa-reference-run.XXXXXX)"
trap 'rm -rf "$work"' EXIT

# Run 1: screenshots along the still period, and the stats that date them.
run() {   # run NAME CFG_BODY [engine args]: one engine run of the cfg, screenshots copied to OUT
  local name="$1" cfg_body="$2"
  shift 2
  pa_engine_prepare "$work/$name" "$module"
  printf 'set r_pt_pipeline 0\n%b' "$cfg_body" >"$(pa_engine_cfg "$work/$name" ref)"
  pa_engine_run "$work/$name" "$out/$name.log" "${REFERENCE_TIMEOUT:-1800}" 640 360 pathtracer \
    +set sv_pure 0 +set cg_drawGun 1 +set cg_draw2D 1 +set cg_bobup 0 +set cg_bobpitch 0 \
    +set cg_bobroll 0 +set con_notifytime -1 +set r_pt_preset reference +set r_pt_stats 1 "$@" \
    +devmap "$map" +exec ref.cfg
  cp "$work/$name"/home/baseoa/screenshots/*.tga "$out/" 2>/dev/null || true
}
# `wait 2` is one rendered frame (two command-buffer ticks per frame: tests/fidelity/capture_frames.sh).
body="wait 60\nnoclip\nsetviewpos $view\n"
for ((f = step; f <= max; f += step)); do body+="wait $((2 * step))\nscreenshot still_$(printf %04d "$f")\n"; done
body+="wait 4\nquit\n"
run still "$body" "$@"
# Frames accumulated every 2 s of the still view (one r_pt_stats line per 2 s): the lines after
# the count last dropped (the teleport restarts it).
mapfile -t counts < <(grep -o 'accumulated=[0-9]*' "$out/still.log" | cut -d= -f2 |
  awk 'BEGIN { start = 1 } { v[NR] = $1; if (NR > 1 && $1 < v[NR - 1]) start = NR } END { for (i = start; i <= NR; i++) print v[i] }')
echo "frames accumulated every 2 s: ${counts[*]}"
line=$(( seconds / 2 - 1 )); (( line >= 0 )) || line=0
(( ${#counts[@]} > line + 1 )) || { echo "the still view lasted under $seconds s; raise MAX"; exit 1; }
at="${counts[$line]}"
pick=$(( (at + step / 2) / step * step )); (( pick >= step )) || pick=$step
(( pick <= max )) || pick=$max
echo "after $seconds s: $at frames; compared screenshot: still_$(printf %04d "$pick") ($pick frames of 1 spp)"

# Run 2: the same view, one frame of as many samples, then the converged image.
spp=$(( pick > 256 ? 256 : pick ))
body="wait 60\nnoclip\nsetviewpos $view\nwait 20\nset r_pt_spp $spp\nwait 4\nscreenshot equal_spp\n"
body+="set r_pt_spp 64\nwait $((2 * ref_frames + 2))\nscreenshot converged\nwait 4\nquit\n"
run converge "$body" "$@"
echo "still_$(printf %04d "$pick") against converged: $("$compare" "$out/converged.tga" "$out/still_$(printf %04d "$pick").tga")"
echo "equal_spp ($spp spp, one frame) against converged: $("$compare" "$out/converged.tga" "$out/equal_spp.tga")"
echo "images and logs: $out"
