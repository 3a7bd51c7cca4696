#!/usr/bin/env bash
# scripts/contact_sheet.sh OUT_DIR [options]: the same views of several maps drawn by the stock
# renderer and by our presets side by side, in the real engine (tests/fidelity/capture_view.sh:
# devmap, noclip, setviewpos, screenshot), with each view's mean linear luminance against the
# lightmap preset's (pa-imgcompare's luma_ratio). Writes OUT_DIR/contact_sheet.png (one row per
# view, one column per renderer, labelled), OUT_DIR/luminance.tsv and the screenshots. Game
# images stay out of the repository: OUT_DIR is yours.
#   --maps "a b ..."     maps (default: oa_dm1 oa_dm3 oasago2 oa_rpg3dm2 wrackdm17 czest1dm)
#   --views N            spawn points per map used as views (default 2: the first and the middle one)
#   --presets "..."      our presets (default "lightmap path"); opengl1 is always the first column
#   --module PATH        our module (default build/port/engine_glue/renderer_pathtracer_x86_64.so)
#   --wait TICKS         command-buffer ticks between arriving at a view and its screenshot
#                        (default 40; at com_maxfps 20 one tick is one frame: what a player
#                        standing still for 2 s sees)
#   -- ARGS              more engine arguments for our presets (e.g. +set r_pt_scale 1)
# Needs ioquake3, openarena, xvfb-run (scripts/setup.sh) and ImageMagick's montage.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$here/tests/fidelity/engine_env.sh"
out="${1:?usage: contact_sheet.sh OUT_DIR [--maps ...] [--views N] [--presets ...] [--module PATH] [--wait T] [-- ARGS]}"
shift
maps="oa_dm1 oa_dm3 oasago2 oa_rpg3dm2 wrackdm17 czest1dm"
views=2
presets="lightmap path"
module="$here/build/port/engine_glue/renderer_pathtracer_x86_64.so"
wait_ticks=40
extra=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --maps) maps="$2"; shift 2 ;;
    --views) views="$2"; shift 2 ;;
    --presets) presets="$2"; shift 2 ;;
    --module) module="$2"; shift 2 ;;
    --wait) wait_ticks="$2"; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) echo "contact_sheet: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ "$views" =~ ^[1-9][0-9]*$ && "$wait_ticks" =~ ^[1-9][0-9]*$ ]] || { echo "contact_sheet: bad --views or --wait" >&2; exit 2; }
pa_engine_available || { echo "contact_sheet: needs ioquake3, openarena and xvfb-run (scripts/setup.sh)" >&2; exit 2; }
command -v montage >/dev/null || { echo "contact_sheet: needs ImageMagick (apt-get install imagemagick)" >&2; exit 2; }
[[ -f "$module" ]] || { echo "contact_sheet: no module at $module (build first)" >&2; exit 2; }
compare="$here/build/tests/fidelity/pa-imgcompare"
[[ -x "$compare" ]] || { echo "contact_sheet: no $compare (build first)" >&2; exit 2; }
mkdir -p "$out"

# Spawn points of a map (info_player_deathmatch, else info_player_start), read from its BSP in
# the game's pk3 files: prints "X Y Z YAW" lines, eye height added.
spawn_views() {
  python3 - "$PA_GAME_DIR" "$1" "$views" <<'PY'
import glob, os, re, struct, sys, zipfile
game, name, count = sys.argv[1], sys.argv[2], int(sys.argv[3])
data = None
for pk3 in sorted(glob.glob(os.path.join(game, "*.pk3")), reverse=True):
    with zipfile.ZipFile(pk3) as z:
        if "maps/%s.bsp" % name in z.namelist():
            data = z.read("maps/%s.bsp" % name)
            break
if data is None or data[:4] != b"IBSP":
    sys.exit("no maps/%s.bsp in %s" % (name, game))
offset, length = struct.unpack_from("<ii", data, 8)   # lump 0: entities
text = data[offset:offset + length].decode("latin-1")
spawns = []
for block in re.findall(r"\{([^{}]*)\}", text):
    keys = dict(re.findall(r'"([^"]*)"\s+"([^"]*)"', block))
    if keys.get("classname") in ("info_player_deathmatch", "info_player_start") and "origin" in keys:
        x, y, z = (float(v) for v in keys["origin"].split()[:3])
        spawns.append((keys["classname"] != "info_player_deathmatch", x, y, z + 26.0, float(keys.get("angle", "0"))))
spawns.sort(key=lambda s: s[0])   # deathmatch spawns first, keeping map order within each kind
if not spawns:
    sys.exit("%s: no spawn point" % name)
picks = [spawns[0]] + [spawns[(i * len(spawns)) // count] for i in range(1, count)]
for _, x, y, z, yaw in picks[:count]:
    print("%.1f %.1f %.1f %.1f" % (x, y, z, yaw))
PY
}

columns=(opengl1 $presets)
printf 'map\tview\tposition\t%s\n' "$(printf '%s/lightmap luma\t' "${columns[@]}" | sed 's/\t$//')" >"$out/luminance.tsv"
tiles=()
for map in $maps; do
  mapfile -t positions < <(spawn_views "$map")
  for column in "${columns[@]}"; do
    dir="$out/$map/$column"
    if [[ "$column" == opengl1 ]]; then
      "$here/tests/fidelity/capture_view.sh" "$dir" opengl1 "" "$map" "${positions[@]}" -- >/dev/null
    else
      CAPTURE_WAIT="$wait_ticks" "$here/tests/fidelity/capture_view.sh" "$dir" pathtracer "$module" "$map" "${positions[@]}" -- \
        +set r_pt_preset "$column" "${extra[@]}" >/dev/null
    fi
  done
  for ((v = 1; v <= ${#positions[@]}; ++v)); do
    row="$map	$v	${positions[v - 1]}"
    for column in "${columns[@]}"; do
      shot="$out/$map/$column/view_$v.tga"
      ratio="$("$compare" "$out/$map/lightmap/view_$v.tga" "$shot" 2>/dev/null | sed -n 's/.*luma_ratio=\([^ ]*\).*/\1/p' || true)"
      row+="	${ratio:-n/a}"
      tiles+=(-label "$map $v $column ${ratio:-n/a}" "$shot")
    done
    printf '%s\n' "$row" >>"$out/luminance.tsv"
  done
done
# The labels in a font the machine has (montage's default, Helvetica, is missing without
# Ghostscript's fonts, and montage then fails after writing an unlabelled sheet).
font=(); label_font="$(fc-match -f '%{file}' sans 2>/dev/null || true)"
[[ -f "$label_font" ]] && font=(-font "$label_font")
montage "${tiles[@]}" -tile "${#columns[@]}x" -geometry 480x270+4+4 "${font[@]}" -pointsize 16 "$out/contact_sheet.png"
column -t -s $'\t' "$out/luminance.tsv"
echo "contact sheet: $out/contact_sheet.png"
