#!/usr/bin/env bash
# scripts/record_demos.sh [options]: records the benchmark demos of tests/demos with bots, in
# Debian's unmodified ioquake3 + OpenArena and the stock opengl1 renderer under xvfb-run.
# Each demo is a listen server started with `devmap MAP` (cheats on), bots added with `addbot`,
# and a console script (a .cfg of `wait`-separated commands) that either spectates and follows a
# bot ("follow") or plays with god mode and every weapon, firing one weapon while turning and
# walking ("fight"). The recording runs a little longer than needed and is then cut to
# --messages server messages (pa_demo_truncate), so every demo has the same length whatever
# the frame rate of the recording machine. Bots play differently on every run: a re-recorded
# demo shows the same map and kind of action, not the same frames.
#   --out DIR        where the .dm_71 files go (default tests/demos)
#   --only "a b"     record only these demos (names from the table below)
#   --messages N     server messages kept per demo (default 600: 30 s of game at 20 snapshots/s)
#   --keep DIR       keep each recording's engine log in DIR
# Exit 77 when the engine, the game data or xvfb-run are missing; 1 when a recording fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tests/fidelity/engine_env.sh"

out="$root/tests/demos"; only=""; messages=600; keep=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --only) only="$2"; shift 2 ;;
    --messages) messages="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    -h|--help) sed -n '2,16p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "record_demos: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ "$messages" =~ ^[1-9][0-9]*$ ]] || { echo "record_demos: bad --messages $messages" >&2; exit 2; }
pa_engine_available || { echo "skipped: ioquake3, openarena or xvfb-run not installed"; exit 77; }

# name | map | g_gametype (0 free for all, 4 capture the flag) | bots (NAME:SKILL[:TEAM]) | script
demos=(
  "dm1_ffa       | oa_dm1         | 0 | Sarge:3 Grism:3 Kyonshi:3                                   | follow"
  "wrackdm17_ffa | wrackdm17      | 0 | Sarge:4 Grism:4 Kyonshi:4 Major:4 Angelyss:4                | follow"
  "sago2_ctf     | oasago2        | 4 | Sarge:3:red Grism:3:red Major:3:red Kyonshi:3:blue Liz:3:blue Tony:3:blue | follow"
  "dm3_rockets   | oa_dm3         | 0 | Sarge:2 Grism:2 Kyonshi:2                                   | fight 5"
  "rpg3dm2_plasma| oa_rpg3dm2     | 0 | Sarge:2 Grism:2 Kyonshi:2                                   | fight 8"
  "czest1dm_ffa  | czest1dm       | 0 | Sarge:3 Grism:3 Kyonshi:3 Major:3                           | follow"
)

# The engine's command buffer runs `wait` ticks at two per rendered frame; com_maxfps 60 makes
# 120 ticks a second of game when the machine keeps up (fewer when it does not, which only makes
# the recording longer in game time).
ticks_per_second=120
record_seconds=$(( messages / 20 + 8 ))

# follow: join the spectators and follow the first bot (client 1) for the whole recording.
follow_script() {
  local name="$1"
  printf 'team spectator\nwait 60\nfollow 1\nwait 60\nrecord %s\n' "$name"
  printf 'wait %d\n' $(( record_seconds * ticks_per_second ))
  printf 'stoprecord\nwait 10\nquit\n'
}

# fight WEAPON: god mode and every weapon, then rounds of firing WEAPON (5 rocket launcher,
# 8 plasma gun: both cast dynamic lights) while turning left, walking forward and turning right.
fight_script() {
  local name="$1" weapon="$2" round=0 rounds=$(( record_seconds / 6 + 1 ))
  printf 'god\ngive all\nwait 20\nweapon %d\nwait 60\nrecord %s\n' "$weapon" "$name"
  while (( round < rounds )); do
    printf '+attack\n+left\nwait 180\n-left\n+forward\nwait 180\n-forward\n'
    printf '+right\nwait 120\n-right\n-attack\n+back\nwait 120\n-back\n+moveup\nwait 20\n-moveup\n'
    round=$(( round + 1 ))
  done
  printf 'stoprecord\nwait 10\nquit\n'
}

trim() { local s="$1"; s="${s#"${s%%[![:space:]]*}"}"; echo "${s%"${s##*[![:space:]]}"}"; }

record_one() {  # record_one NAME MAP GAMETYPE BOTS SCRIPT...
  local name="$1" map="$2" gametype="$3" bots="$4"; shift 4
  local work; work="$(mktemp -d /tmp/pa-record.XXXXXX)"
  pa_engine_prepare "$work"
  local cfg; cfg="$(pa_engine_cfg "$work" record)"
  : >"$cfg"
  local bot bot_name bot_skill bot_team
  for bot in $bots; do
    IFS=: read -r bot_name bot_skill bot_team <<<"$bot"
    echo "addbot $bot_name $bot_skill ${bot_team:-}" >>"$cfg"
  done
  echo "wait 120" >>"$cfg"
  case "$1" in
    follow) follow_script "$name" >>"$cfg" ;;
    fight) fight_script "$name" "$2" >>"$cfg" ;;
    *) echo "record_demos: unknown script $1" >&2; return 1 ;;
  esac
  echo "record_demos: recording $name ($map, about $record_seconds s) ..." >&2
  local log="$work/record.log" status=0
  pa_engine_run "$work" "$log" $(( record_seconds * 8 + 120 )) 640 360 opengl1 \
    +set bot_enable 1 +set g_doWarmup 0 +set sv_pure 0 +set com_maxfps 60 \
    +set fraglimit 0 +set timelimit 0 +set capturelimit 0 +set g_gametype "$gametype" \
    +devmap "$map" +wait 100 +exec record.cfg || status=$?
  [[ -n "$keep" ]] && { mkdir -p "$keep"; cp "$log" "$keep/$name.log"; }
  local recorded="$work/home/baseoa/demos/$name.dm_71"
  # A run stopped by the time limit (a slow machine) still leaves a usable demo: the cut keeps
  # whole messages only.
  local kept=0
  [[ -f "$recorded" ]] && kept="$(pa_demo_truncate "$work/cut.dm_71" "$messages" "$recorded")"
  if [[ "$kept" -ne "$messages" ]]; then
    echo "record_demos: $name failed (status $status, $kept messages); log tail:" >&2
    grep -a -v GL_EXTENSIONS "$log" | tail -n 15 >&2
    rm -rf "$work"; return 1
  fi
  cp "$work/cut.dm_71" "$out/$name.dm_71"
  echo "$name: $map, $kept messages, $(stat -c %s "$out/$name.dm_71") bytes"
  rm -rf "$work"
}

mkdir -p "$out"
failed=0
for entry in "${demos[@]}"; do
  IFS='|' read -r name map gametype bots script <<<"$entry"
  name="$(trim "$name")"
  [[ -z "$only" || " $only " == *" $name "* ]] || continue
  # shellcheck disable=SC2086  # the script field is a command and its arguments
  record_one "$name" "$(trim "$map")" "$(trim "$gametype")" "$(trim "$bots")" $script || failed=1
done
exit $failed
