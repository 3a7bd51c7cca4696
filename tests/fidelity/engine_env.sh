# Shared shell helpers (source this file) to run Debian's unmodified ioquake3 with OpenArena
# under xvfb-run, with either our module (cl_renderer pathtracer) or a stock renderer.
# Used by tests/fidelity/capture_frames.sh, tests/regress/capture_demo.sh and scripts/engine_bench.sh.
#   pa_engine_available              -> 0 when the engine, the game data and xvfb-run exist
#   pa_engine_prepare WORK [MODULE]  -> WORK/basepath (module + baseoa link) and WORK/home
#   pa_engine_cfg WORK NAME          -> prints the path of WORK's NAME.cfg (the engine execs it)
#   pa_tick_screenshots_cfg CFG PREFIX TICKS -> CFG takes screenshot PREFIX_NNNN at each tick, then quits
#   pa_capture_demo_ticks OUT RENDERER MODULE DEMO PREFIX TICKS SECONDS [engine args...]
#        -> OUT/PREFIX_NNNN.tga (.exr) at each tick of a timedemo of DEMO, and OUT/engine.log;
#        r_pt_pipeline is PA_CAPTURE_PIPELINE (default 0: each tick shows its own world view)
#   pa_engine_run WORK LOG SECONDS WIDTH HEIGHT RENDERER [engine args...]
#        RENDERER is "pathtracer" (our module) or a stock name such as "opengl1".
#        Returns the engine's exit status (124 on timeout). The X screen is WIDTHxHEIGHT unless
#        PA_XVFB_SCREEN (e.g. 1024x768x24) says otherwise. PA_ENGINE_PRELOAD (a library path)
#        is preloaded into the engine alone (tests/regress's pa_fixed_rand.so).
PA_ENGINE="${PA_ENGINE:-/usr/lib/ioquake3/ioquake3}"
PA_GAME_DIR="${PA_GAME_DIR:-/usr/lib/openarena/baseoa}"

pa_engine_available() {
  [[ -x "$PA_ENGINE" && -d "$PA_GAME_DIR" ]] && command -v xvfb-run >/dev/null
}

pa_engine_prepare() {
  local work="$1" module="${2:-}"
  mkdir -p "$work/basepath" "$work/home/baseoa"
  if [[ -n "$module" ]]; then
    cp -f "$module" "$work/basepath/renderer_pathtracer_x86_64.so"
    cp -f "$module" "$work/basepath/renderer_pathtracer.so"
  fi
  ln -sfn "$PA_GAME_DIR" "$work/basepath/baseoa"
}

pa_engine_cfg() { echo "$1/home/baseoa/$2.cfg"; }

pa_engine_run() {
  local work="$1" log="$2" seconds="$3" width="$4" height="$5" renderer="$6" status=0
  shift 6
  local preload=() arg plus=14   # the "+" commands below
  for arg in "$@"; do [[ "$arg" == +* ]] && plus=$((plus + 1)); done
  # The engine splits its command line into at most 32 lines, the first the text before any
  # "+" (ioquake3 Com_ParseCommandLine): past 31 "+" commands the rest is glued to the 31st
  # (a "+demo NAME +exec CFG" so glued fails, and the engine waits in the menu until the
  # timeout). Refuse instead.
  if [[ $plus -gt 31 ]]; then
    echo "pa_engine_run: $plus '+' commands, the engine takes 31: set cvars in the cfg it execs" >"$log"
    cat "$log" >&2
    return 2
  fi
  [[ -n "${PA_ENGINE_PRELOAD:-}" ]] && preload=(env "LD_PRELOAD=$PA_ENGINE_PRELOAD${LD_PRELOAD:+:$LD_PRELOAD}")
  # fs_homepath is given explicitly: screenshots land in WORK/home/baseoa/screenshots.
  HOME="$work/home" timeout "$seconds" xvfb-run -a -s "-screen 0 ${PA_XVFB_SCREEN:-${width}x${height}x24}" "${preload[@]}" "$PA_ENGINE" \
    +set com_basegame baseoa +set fs_basepath "$work/basepath" +set fs_homepath "$work/home" \
    +set com_legacyprotocol 71 +set com_protocol 71 +set cl_renderer "$renderer" \
    +set r_mode -1 +set r_customwidth "$width" +set r_customheight "$height" +set r_fullscreen 0 \
    +set s_initsound 0 +set bot_enable 0 +set com_introplayed 1 +set cl_allowDownload 0 \
    "$@" >"$log" 2>&1 || status=$?
  # timeout stops xvfb-run, not the engine under it: end this run's engine too (its home path
  # names it), so that a timed-out run leaves no process behind.
  if [[ "$status" -eq 124 || "$status" -eq 137 ]]; then
    pkill -KILL -f -- "fs_homepath $work/home" 2>/dev/null || true
  fi
  return "$status"
}

# pa_tick_screenshots_cfg CFG PREFIX "T1 T2 ...": writes the engine script CFG that takes
# screenshot PREFIX_NNNN at each command-buffer tick T (increasing), then quits; returns 2 (with a
# message) when the ticks do not increase. With `timedemo 1`, tick N is the same game moment in
# every run (tests/fidelity/README.md).
pa_tick_screenshots_cfg() {
  local cfg="$1" prefix="$2" ticks="$3" previous=0 tick
  : >"$cfg"
  for tick in $ticks; do
    [[ "$tick" =~ ^[0-9]+$ && "$tick" -gt "$previous" ]] || { echo "ticks must increase: $ticks"; return 2; }
    printf 'wait %d\nscreenshot %s_%04d\n' $((tick - previous)) "$prefix" "$tick" >>"$cfg"
    previous="$tick"
  done
  printf 'wait 5\nquit\n' >>"$cfg"
}

# pa_capture_demo_ticks OUT RENDERER MODULE DEMO PREFIX "T1 T2 ..." SECONDS [engine args...]:
# plays DEMO (a name in the game's demos/, e.g. demo088-test1, or a path to a .dm_71 file) as a
# timedemo under xvfb-run, at most SECONDS, with RENDERER ("pathtracer": MODULE is our .so; or a
# stock one, MODULE ignored), and writes OUT/PREFIX_NNNN.tga at each command-buffer tick T (also
# OUT/PREFIX_NNNN.exr where our module writes its film: r_pt_captureExr 1) and OUT/engine.log.
# Size CAPTURE_WIDTH x CAPTURE_HEIGHT (640x360 by default). The HUD leaves out what follows the
# engine's wall clock rather than the demo, so that a tick is the same picture in every run: console
# notify lines (shown for con_notifytime seconds of wall-clock time) and the lagometer (its
# snapshot bars plot "ping", which in demo playback is the wall-clock time since the engine
# started); engine args come after and may set them back. Returns 0, 1 (the engine failed or a
# tick is missing), 2 (no such demo file, bad name or ticks) or 77 (engine, game data or
# xvfb-run missing), with a message.
pa_capture_demo_ticks() (
  set -euo pipefail
  local out="$1" renderer="$2" module="$3" demo="$4" prefix="$5" ticks="$6" seconds="$7"
  shift 7
  local width="${CAPTURE_WIDTH:-640}" height="${CAPTURE_HEIGHT:-360}" work status tick
  pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }
  work="$(mktemp -d /tmp/pa-capture.XXXXXX)"
  trap 'rm -rf "$work"' EXIT
  if [[ "$renderer" == pathtracer ]]; then pa_engine_prepare "$work" "$module"; else pa_engine_prepare "$work"; fi
  if [[ "$demo" == *.dm_71 ]]; then
    [[ -f "$demo" ]] || { echo "no demo file $demo"; exit 2; }
    mkdir -p "$work/home/baseoa/demos"
    cp "$demo" "$work/home/baseoa/demos/pa_capture.dm_71"
    demo=pa_capture
  fi
  [[ "$demo" =~ ^[A-Za-z0-9_.-]+$ ]] || { echo "bad demo name: $demo"; exit 2; }
  pa_tick_screenshots_cfg "$(pa_engine_cfg "$work" capture)" "$prefix" "$ticks" || exit 2
  # Each tick shows its own frame's world view (r_pt_pipeline would show the frame before's):
  # set in the cfg, as the engine takes at most 32 "+" commands on its command line.
  sed -i "1i set r_pt_pipeline ${PA_CAPTURE_PIPELINE:-0}" "$(pa_engine_cfg "$work" capture)"
  mkdir -p "$out"
  status=0
  pa_engine_run "$work" "$out/engine.log" "$seconds" "$width" "$height" "$renderer" \
    +set timedemo 1 +set com_maxfps 0 +set cg_drawFPS 0 +set con_notifytime -1 +set cg_lagometer 0 \
    "$@" +demo "$demo" +exec capture.cfg || status=$?
  cp "$work"/home/baseoa/screenshots/"$prefix"_*.tga "$out/" 2>/dev/null || true
  cp "$work"/home/baseoa/screenshots/"$prefix"_*.exr "$out/" 2>/dev/null || true
  if [[ $status -ne 0 ]]; then echo "engine exited with status $status (log: $out/engine.log)"; exit 1; fi
  pa_engine_used_renderer "$out/engine.log" "$renderer" || { echo "renderer $renderer was not used (log: $out/engine.log)"; exit 1; }
  for tick in $ticks; do
    [[ -f "$out/$(printf '%s_%04d.tga' "$prefix" "$tick")" ]] || { echo "tick $tick was not captured (log: $out/engine.log)"; exit 1; }
  done
)

# True when LOG shows the engine ran RENDERER (ours prints its banner; a stock one must not
# have been replaced by a fallback).
pa_engine_used_renderer() {
  local log="$1" renderer="$2"
  if [[ "$renderer" == pathtracer ]]; then
    grep -q "PathArena path tracer renderer" "$log" && ! grep -q 'Trying to load "renderer_opengl' "$log"
  else
    grep -q "Trying to load \"renderer_${renderer}" "$log" && ! grep -q "failed to load\|Falling back" "$log"
  fi
}

# pa_demo_truncate OUT MESSAGES [SOURCE]: writes the demo SOURCE cut after MESSAGES server
# messages, with the end-of-demo marker (-1, -1) appended, so that a timedemo of it ends by itself
# and prints its "N frames X seconds Y fps" line; prints the number of messages kept. SOURCE is a
# .dm_71 file; without it, OpenArena's demo088-test1 (read from pak6-patch088.pk3; 3389 messages,
# about 170 s of game at 20 snapshots/s). A recorded demo holds one server message per snapshot.
# OUT /dev/null with a large MESSAGES counts a demo's messages. Needs python3 (zip + struct).
pa_demo_truncate() {
  local out="$1" messages="$2" source="${3:-}"
  python3 - "$out" "$messages" "$source" "$PA_GAME_DIR/pak6-patch088.pk3" <<'PY'
import struct, sys, zipfile
out, limit, source, pk3 = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
if source:
    with open(source, "rb") as f:
        data = f.read()
else:
    data = zipfile.ZipFile(pk3).read("demos/demo088-test1.dm_71")
# Each message: sequence (int32), length (int32), then length bytes; (-1, -1) ends the demo.
offset = count = 0
while count < limit and offset + 8 <= len(data):
    sequence, length = struct.unpack_from("<ii", data, offset)
    if length < 0 or offset + 8 + length > len(data):
        break
    offset += 8 + length
    count += 1
with open(out, "wb") as f:
    f.write(data[:offset] + struct.pack("<ii", -1, -1))
print(count)
PY
}
