#!/usr/bin/env bash
# scripts/reference_convergence.sh MAP "X Y Z YAW" [OUT_DIR] [-- engine args...]
# How far the `reference` preset gets while the player stands still, in the real engine: loads MAP
# (devmap, noclip, gun and 2D on, no view bob) with our module at 640x360, stands at the view and
# takes a screenshot every STEP frames (default 32) up to MAX frames (default 320), printing how
# many frames had accumulated every 2 s (r_pt_stats' period). Then, in the same run and view:
#   - `equal_spp`: one frame of EQUAL_SPP samples (default 256): what an offline render of as
#     many samples gives, to set beside the screenshot after as many frames;
#   - `converged`: r_pt_spp 64 for REF_FRAMES frames (default 64, so 4096 spp) with r_pt_seed
#     REF_SEED (default 1): samples independent of the still view's, which are the first of the
#     same sequence under seed 0 (with the same seed the stills would read closer than they are).
# Prints PSNR / SSIM / FLIP (pa-imgcompare) against converged of the screenshot nearest SECONDS
# (default 10, even) of standing still, of the one after EQUAL_SPP frames and of equal_spp: whole,
# and on CROP="X,Y,W,H" (screenshot pixels) when set. Accumulation loses nothing in play when
# the last two agree. Everything is one run: `setviewpos` pushes the player forward and noclip's
# friction stops it after a distance that depends on the frame times, so two runs stand a unit or
# two apart (the converged images of two runs read 27.8 dB against each other on a ceiling lamp).
# Slow: `converged` takes minutes. Exit 77 when the engine, the game data or xvfb-run are missing.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tests/fidelity/engine_env.sh"
map="$1"; view="$2"; shift 2
out="$(mktemp -d /tmp/pa-reference.XXXXXX)"
[[ $# -gt 0 && "$1" != "--" ]] && { out="$1"; shift; }
[[ $# -gt 0 ]] && shift
module="${PA_MODULE:-$root/build/port/engine_glue/renderer_pathtracer_x86_64.so}"
compare="${PA_IMGCOMPARE:-$root/build/tests/fidelity/pa-imgcompare}"
step="${STEP:-32}"; max="${MAX:-320}"; seconds="${SECONDS_STILL:-10}"; ref_frames="${REF_FRAMES:-64}"
equal_spp="${EQUAL_SPP:-256}"; ref_seed="${REF_SEED:-1}"
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
[[ "$map" =~ ^[A-Za-z0-9_]+$ ]] || { echo "bad map name: $map"; exit 2; }
[[ "$view" =~ ^-?[0-9.]+\ -?[0-9.]+\ -?[0-9.]+\ -?[0-9.]+$ ]] || { echo "bad view '$view' (X Y Z YAW)"; exit 2; }
[[ "$equal_spp" =~ ^[0-9]+$ ]] && (( equal_spp >= 1 )) || { echo "bad EQUAL_SPP '$equal_spp'"; exit 2; }
[[ "$ref_seed" =~ ^[0-9]+$ ]] || { echo "bad REF_SEED '$ref_seed'"; exit 2; }
[[ -x "$compare" ]] || { echo "missing $compare (build the tree first)"; exit 2; }
mkdir -p "$out"
work="$(mktemp -d /tmp/pa-reference-run.XXXXXX)"
trap 'rm -rf "$work"' EXIT

# One run: screenshots along the still period, then equal_spp and converged from the same place.
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
# `wait 2` is one rendered frame (two command-buffer ticks per frame: tests/fidelity/capture_frames.sh);
# after a cvar change it is one frame rendered with it, which the screenshot then reads.
body="wait 60\nnoclip\nsetviewpos $view\n"
for ((f = step; f <= max; f += step)); do body+="wait $((2 * step))\nscreenshot still_$(printf %04d "$f")\n"; done
body+="set r_pt_spp $equal_spp\nwait 2\nscreenshot equal_spp\n"
body+="set r_pt_seed $ref_seed\nset r_pt_spp 64\nwait $((2 * ref_frames))\nscreenshot converged\nwait 4\nquit\n"
run still "$body" "$@"
# Frames accumulated every 2 s of the still view (one r_pt_stats line per 2 s): the lines after
# the count last dropped (the teleport restarts it), up to the last still screenshot.
last_still="still_$(printf %04d "$(( max / step * step ))")"
mapfile -t counts < <(awk -v last="Wrote screenshots/$last_still" '
  index($0, last) { exit }
  /accumulated=/ { n = $0; sub(/.*accumulated=/, "", n); sub(/ .*/, "", n); v[++k] = n + 0; if (k > 1 && v[k] < v[k - 1]) start = k }
  END { if (!start) start = 1; for (i = start; i <= k; i++) print v[i] }' "$out/still.log")
echo "frames accumulated every 2 s: ${counts[*]}"
line=$(( seconds / 2 - 1 )); (( line >= 0 )) || line=0
(( ${#counts[@]} > line + 1 )) || { echo "the still view lasted under $seconds s; raise MAX"; exit 1; }
at="${counts[$line]}"
pick=$(( (at + step / 2) / step * step )); (( pick >= step )) || pick=$step
(( pick <= max )) || pick=$max
echo "after $seconds s: $at frames; nearest screenshot: still_$(printf %04d "$pick")"
# The frames equal_spp holds, from the log: r_pt_stats prints a line after every frame slower
# than its 2 s period, so the last count before "Wrote screenshots/equal_spp" is its own.
equal_frames=$(awk '/accumulated=/ { n = $0; sub(/.*accumulated=/, "", n); sub(/ .*/, "", n) }
  /Wrote screenshots\/equal_spp/ { print n; exit }' "$out/still.log")
[[ "$equal_frames" == 1 ]] || echo "warning: equal_spp holds ${equal_frames:-an unknown number of} frames, not one"
compare_both() {   # compare_both LABEL IMAGE: against converged, whole and on CROP when set
  [[ -f "$2" ]] || { echo "$1: no screenshot"; return; }
  echo "$1 against converged: $("$compare" "$out/converged.tga" "$2")"
  [[ -z "${CROP:-}" ]] || echo "$1 against converged, crop $CROP: $("$compare" "$out/converged.tga" "$2" --crop "$CROP")"
}
compare_both "still_$(printf %04d "$pick") (after $seconds s)" "$out/still_$(printf %04d "$pick").tga"
equal_still=$(( (equal_spp + step / 2) / step * step ))
compare_both "still_$(printf %04d "$equal_still")" "$out/still_$(printf %04d "$equal_still").tga"
compare_both "equal_spp ($equal_spp spp, one frame)" "$out/equal_spp.tga"
echo "images and logs: $out"
