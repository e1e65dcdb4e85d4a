#!/bin/bash
# Bad input through the CLI, without an OpenCL device (runs in the sanitizer
# build too): inputs generated here (100 MB lines, random bytes, endless
# devices) exit 2 naming the file, in bounded time (timeout) and memory (peak
# RSS within 64 MB of a small bad input's); image sizes and outputs are checked
# before rendering; a failed or killed run leaves an existing output as it
# was; SIGTERM writes the image so far; a scene lit only by its sky is valid;
# emissions too bright or too faint for float are refused or warned about.
# usage: bash tests/cli_robust_input.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
SCENE_TAIL='camera position 0 1 -3 direction 0 0 1 fov 40
spectrum flat equal
material light emit flat 1
tri light 0 0 0 1 0 0 0 1 0'

# Peak RSS in KB of a command (GNU time writes it to $T/rss); sets $rc.
measure() {
  /usr/bin/time -f "%M" -o "$T/time" timeout 20 "$@" >/dev/null 2>"$T/err"; rc=$?
  tail -n 1 "$T/time" > "$T/rss"  # a failing command adds a line before
}

# expect_bad NAME FILE CMD...: exit 2 and a message naming FILE (basename).
expect_bad() {
  local what=$1 file=$2; shift 2
  measure "$@"
  if [ $rc -eq 2 ] && grep -q "$(basename "$file")" "$T/err"; then ok
  else bad "$what: rc $rc: $(head -c 300 "$T/err")"; fi
}

# 1. 100 MB lines (generated, not committed): a 100 MB token in a scene, a
#    MiniLight file and a CSV row; memory stays near a small bad file's.
expect_bad "small bad scene" "$ROOT/tests/bad-inputs/scene_truncated.scene" \
  "$BIN" render "$ROOT/tests/bad-inputs/scene_truncated.scene" -o "$T/o.png"
base_render=$(cat "$T/rss")
expect_bad "small bad csv" "$ROOT/tests/bad-inputs/nan_value.csv" \
  "$BIN" spectrum "$ROOT/tests/bad-inputs/nan_value.csv"
base_spectrum=$(cat "$T/rss")
big() { head -c $((100 << 20)) /dev/zero | tr '\0' "$1"; }
{ echo "image 4 4"; printf 'spp '; big 7; echo; echo "$SCENE_TAIL"; } > "$T/long.scene"
{ echo "#MiniLight"; big 9; echo; } > "$T/long.ml.txt"
{ echo "wavelength_nm,value"; printf '380,'; big 1; echo; } > "$T/long.csv"
for f in long.scene long.ml.txt; do
  expect_bad "100 MB line in $f" "$f:2:" "$BIN" render "$T/$f" -o "$T/o.png"
  [ "$(cat "$T/rss")" -lt $((base_render + 65536)) ] && ok || bad "$f: peak RSS $(cat "$T/rss") KB"
done
expect_bad "100 MB line in a CSV" "long.csv:2:" "$BIN" spectrum "$T/long.csv"
[ "$(cat "$T/rss")" -lt $((base_spectrum + 65536)) ] && ok || bad "long.csv: peak RSS $(cat "$T/rss") KB"
rm -f "$T"/long.*

# 2. Binary garbage: 1 MB of random bytes as each kind of input, and devices
#    that never end (as the scene and as a spectrum file a scene names).
head -c $((1 << 20)) /dev/urandom > "$T/garbage.scene"
cp "$T/garbage.scene" "$T/garbage.csv"
{ echo "#MiniLight"; cat "$T/garbage.scene"; } > "$T/garbage.ml.txt"
for f in garbage.scene garbage.ml.txt; do
  expect_bad "$f" "$f" "$BIN" render "$T/$f" -o "$T/o.png"
done
expect_bad garbage.csv garbage.csv "$BIN" spectrum "$T/garbage.csv"
for dev in /dev/zero /dev/urandom; do
  expect_bad "scene $dev" "$dev" "$BIN" render "$dev" -o "$T/o.png"
  expect_bad "spectrum $dev" "$dev" "$BIN" spectrum "$dev"
  { echo "image 4 4"; echo "$SCENE_TAIL"; echo "spectrum d file $dev"; } > "$T/dev.scene"
  expect_bad "scene naming $dev" dev.scene "$BIN" render "$T/dev.scene" -o "$T/o.png"
done

# 3. Refused before rendering: a render of a million samples per pixel on the
#    CPU would outlast `timeout 20`, so exit 2 (not 124) shows nothing ran.
slow=(--backend cpu --spp 1000000 --width 64 --height 64)
touch "$T/file"
for o in "$T/nodir/x.png" "$T/file/x.png" /proc/self/x.png "$T/x.bmp" "$T"; do
  timeout 20 "$BIN" render "${slow[@]}" -o "$o" 2>"$T/err"; rc=$?
  [ $rc -eq 2 ] && grep -q "$o" "$T/err" && ok || bad "output $o: rc $rc $(cat "$T/err")"
done
for size in "--width 0" "--height 16385" "--width -3" "--width 1e9" "--height 12x"; do
  timeout 20 "$BIN" render $size "${slow[@]:0:4}" -o "$T/o.png" 2>"$T/err"; rc=$?
  [ $rc -eq 2 ] && ok || bad "image size '$size': rc $rc"
done

# kept WHAT: the existing output is as it was and no temporary file is left.
kept() {
  [ "$(cat "$T/keep.png")" = "precious" ] && ok || bad "$1: an existing output was changed"
  local tmp; tmp=$(find "$T" -name '*spmtmp*')
  [ -z "$tmp" ] && ok || bad "$1: temporary file left: $tmp"
}

# 4. Nothing lost: an existing output survives a bad scene, a bad second
#    output, and a run killed (SIGKILL) in the middle of rendering.
echo "precious" > "$T/keep.png"
"$BIN" render "$ROOT/tests/bad-inputs/scene_truncated.scene" -o "$T/keep.png" 2>/dev/null; rc=$?
[ $rc -eq 2 ] && ok || bad "bad scene over an existing output: exit $rc"
kept "bad scene"
"$BIN" render "${slow[@]}" -o "$T/keep.png" -o "$T/nodir/y.exr" 2>/dev/null; rc=$?
[ $rc -eq 2 ] && ok || bad "bad second output: exit $rc"
kept "bad second output"
"$BIN" render "${slow[@]}" -o "$T/keep.png" --progress 2>"$T/kill.err" & pid=$!
rendering $pid "$T/kill.err" && ok || bad "SIGKILL: the render never got under way: $(tr '\r' '\n' < "$T/kill.err" | tail -n 2)"
kill -KILL $pid; wait $pid 2>/dev/null; rc=$?
[ $rc -eq 137 ] && ok || bad "SIGKILL: exit status $rc: the render was not running when killed"
kept "SIGKILL in the render"

# 5. SIGTERM: the current pass ends, the image so far replaces the old file
#    (a complete PNG and EXR), exit 130 as for SIGINT.
echo "old" > "$T/term.png"
"$BIN" render "${slow[@]}" -o "$T/term.png" -o "$T/term.exr" --progress 2>"$T/err" & pid=$!
rendering $pid "$T/err" && ok || bad "SIGTERM: the render never got under way: $(tr '\r' '\n' < "$T/err" | tail -n 2)"
kill -TERM $pid; wait $pid; rc=$?
[ $rc -eq 130 ] && ok || bad "SIGTERM exit code $rc"
head -c 4 "$T/term.png" | grep -q PNG && ok || bad "SIGTERM: no PNG written"
oiiotool "$T/term.exr" --printstats 2>/dev/null | grep -q "NanCount: 0 0 0" && ok || bad "SIGTERM: EXR unreadable or not finite"
grep -q "interrupted after" "$T/err" && ok || bad "SIGTERM: no message $(cat "$T/err")"

# 6. Valid stays valid: a scene lit only by its background renders.
"$BIN" render "$ROOT/tests/data/scenes/sky_only.scene" --backend cpu --spp 2 -o "$T/sky.exr" --quiet
[ $? -eq 0 ] && [ -s "$T/sky.exr" ] && ok || bad "sky-only scene refused"

# 7. Light that would vanish: an emission float cannot hold is refused at load
#    (tests/bad-inputs); one whose pixel sums overflow float gets a warning at
#    the end of the render; one so faint that it is subnormal in float gets a
#    warning at load naming its line; ordinary ones get neither.
light_scene() {
  printf '%s\n' "image 8 8" "camera position 0 1 -3 direction 0 0 1 fov 40" "spectrum flat equal" \
    "material wall reflect flat 0.5" "material light emit flat $1" \
    "quad wall -2 0 -2  2 0 -2  2 0 2  -2 0 2" "quad light -0.5 2 -0.5  0.5 2 -0.5  0.5 2 0.5  -0.5 2 0.5" \
    > "$T/light.scene"
  "$BIN" render "$T/light.scene" --backend cpu --spp 16 -o "$T/light.exr" --quiet 2>"$T/err"
}
light_scene 1e38; rc=$?
[ $rc -eq 0 ] && grep -q "overflowed to infinity and were left out" "$T/err" && ok ||
  bad "emission 1e38: rc $rc, no warning about dropped values: $(cat "$T/err")"
light_scene 1e-38; rc=$?
[ $rc -eq 0 ] && grep -q "light.scene:5:.*so faint" "$T/err" && ok ||
  bad "emission 1e-38: rc $rc, no warning naming line 5: $(cat "$T/err")"
# samples that overflow one by one (the light 5 cm from a wall, the camera between)
printf '%s\n' "image 8 8" "camera position -1 0.5 0.03 direction 0 0 1 fov 90" "spectrum flat equal" \
  "material hot emit flat 2e38" "material wall reflect flat 0.5" \
  "quad wall -5 -1 0.05  5 -1 0.05  5 4 0.05  -5 4 0.05" "tri hot -1.5 0 0  -0.5 0 0  -1 1.5 0" \
  > "$T/hot.scene"
"$BIN" render "$T/hot.scene" --backend cpu --spp 8 -o "$T/hot.exr" --quiet 2>"$T/err"; rc=$?
[ $rc -eq 0 ] && grep -q "of the samples (.*) were NaN or infinite and were left out" "$T/err" && ok ||
  bad "non-finite samples: rc $rc, no warning: $(cat "$T/err")"
for e in 1 1e-37 1e37; do
  light_scene $e; rc=$?
  [ $rc -eq 0 ] && [ ! -s "$T/err" ] && ok || bad "emission $e: rc $rc, stderr: $(cat "$T/err")"
done

# 9. Images embedded in a glTF (tools/gltf_embed.py packs the model of
#    tools/make_textured_gltf.py, then one field is spoilt): an image's
#    bufferView out of range or past its buffer, one without a mimeType, a
#    mimeType that is no MIME type, a data: URI of bad base64 or cut short
#    exit 2 naming the file and the field; bytes that are no image render
#    with a warning naming the map that falls back to its factor.
mkdir -p "$T/emb"
python3 "$ROOT/tools/make_textured_gltf.py" "$T/emb" && python3 "$ROOT/tools/gltf_embed.py" \
  "$T/emb/board_mr.gltf" "$T/emb/mr.glb" && python3 "$ROOT/tools/gltf_embed.py" \
  "$T/emb/board_mr.gltf" "$T/emb/mr_data.gltf" || bad "embedded models not written"
spoil() {  # spoil NAME.EXT PYTHON: the packed model with doc (its JSON) changed
  python3 - "$T/emb" "$1" "$2" <<'PY'
import json, struct, sys
folder, name, change = sys.argv[1:]
glb = name.endswith(".glb")
raw = open(folder + ("/mr.glb" if glb else "/mr_data.gltf"), "rb").read()
doc = json.loads(raw[20:20 + struct.unpack("<I", raw[12:16])[0]] if glb else raw)
exec(change)
js = json.dumps(doc).encode()
if glb:
    js += b" " * (-len(js) % 4)
    n = struct.unpack("<I", raw[12:16])[0]
    rest = raw[20 + n:]
    js = struct.pack("<III", 0x46546C67, 2, 20 + len(js) + len(rest)) + \
        struct.pack("<II", len(js), 0x4E4F534A) + js + rest
open(folder + "/" + name, "wb").write(js)
PY
}
embedded_bad() {  # embedded_bad NAME.EXT PYTHON EXPECTED-TEXT
  spoil "$1" "$2" || { bad "$1: not written"; return; }
  printf 'image 4 4\ncamera position 0 0 -2 direction 0 0 1 fov 40\nspectrum flat equal
background both flat 1\nmesh %s\n' "$1" > "$T/emb/$1.scene"
  expect_bad "$1" "$1" "$BIN" render "$T/emb/$1.scene" --backend cpu --spp 1 -o "$T/emb/o.exr"
  grep -qF -- "$3" "$T/err" && ok || bad "$1: does not say '$3': $(head -c 300 "$T/err")"
}
embedded_bad view.glb 'doc["images"][0]["bufferView"] = 99' \
  "images[0].bufferView: not the index of one of the file's"
embedded_bad past.glb 'doc["bufferViews"][doc["images"][1]["bufferView"]]["byteLength"] += 10**6' \
  "images[1].bufferView"
embedded_bad nomime.glb 'del doc["images"][0]["mimeType"]' "images[0]: an image in bufferView"
embedded_bad mime.glb 'doc["images"][0]["mimeType"] = "png"' "images[0].mimeType: 'png' is not a MIME type"
embedded_bad b64.gltf 'u = doc["images"][0]["uri"]; doc["images"][0]["uri"] = u[:40] + "!" + u[41:]' \
  "images[0].uri: a data: URI whose base64 has '!'"
embedded_bad cut.gltf 'doc["images"][1]["uri"] = doc["images"][1]["uri"][:-3]' \
  "images[1].uri: a data: URI whose base64 is"
spoil junk.gltf 'import base64; doc["images"][1]["uri"] = "data:image/png;base64," + base64.b64encode(b"no image at all").decode()'
printf 'image 4 4\ncamera position 0 0 -2 direction 0 0 1 fov 40\nspectrum flat equal
background both flat 1\nmesh junk.gltf\n' > "$T/emb/junk.scene"
"$BIN" render "$T/emb/junk.scene" --backend cpu --spp 1 -o "$T/emb/o.exr" 2> "$T/err"; rc=$?
[ $rc -eq 0 ] && grep -q "junk.gltf: material 'board_mr': metallic-roughness map '\*1' not applied" "$T/err" &&
  ! grep -q "not read for this map yet" "$T/err" && ok || bad "an embedded image that is no image: rc $rc, no warning naming the map: $(cat "$T/err")"

finish
