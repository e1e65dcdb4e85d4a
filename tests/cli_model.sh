#!/bin/bash
# A model in one command: `specmip render FILE` for a .glb, a .gltf, an OBJ
# with its MTL, a binary PLY and an ASCII STL (tools/gen_meshes.py's models),
# on both backends, without a scene file. Each image is framed and lit: the
# pixels that differ from the background (the object's) exist, cover a fair
# part of the frame, and their bounding box lies inside the frame without
# touching its border (a camera that missed gives none; one too close
# touches it); some of them are brighter than the sky alone gives a grey
# object (the key light). The note names the default light; a glTF without
# a material takes glTF's default material, said in a warning; a scene's
# `mesh` statement still refuses an STL without one (cli_mesh.sh).
# usage: bash tests/cli_model.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
python3 "$ROOT/tools/gen_meshes.py" "$T" > /dev/null || { echo "FAIL: gen_meshes.py"; exit 1; }
# cube.gltf without its materials (its buffer is a data URI)
python3 - "$T/cube.gltf" "$T/nomat.gltf" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
d.pop('materials', None)
for m in d['meshes']:
    for p in m['primitives']:
        p.pop('material', None)
json.dump(d, open(sys.argv[2], 'w'))
PY

# mask EXR: "x0 y0 x1 y1 n max" of the pixels whose colour differs from the
# background's by more than 2 % (the background: the value of the top-left
# pixel, which the framing leaves to the sky), and the largest channel sum.
mask() {
  oiiotool --dumpdata "$1" | awk '
    /^ *Pixel/ { gsub(/[(),:]/, " "); x = $2; y = $3
                 if (!have) { r = $4; g = $5; b = $6; have = 1; x0 = 1e9; y0 = 1e9; x1 = -1; y1 = -1 }
                 d = ($4 - r) ^ 2 + ($5 - g) ^ 2 + ($6 - b) ^ 2
                 if (d > (0.02 * (r + g + b) / 3) ^ 2) {
                   n++; if (x < x0) x0 = x; if (y < y0) y0 = y; if (x > x1) x1 = x; if (y > y1) y1 = y }
                 s = $4 + $5 + $6; if (s > mx) mx = s }
    END { printf "%d %d %d %d %d %g\n", x0, y0, x1, y1, n, mx }'
}
W=64 H=48
for backend in cpu opencl; do
  for f in cube.glb cube.gltf cube.obj cube_binary.ply cube_ascii.stl sphere_n.gltf nomat.gltf; do
    "$BIN" render "$T/$f" --backend $backend --spp 8 --width $W --height $H -o "$T/$f.exr" \
      2> "$T/err" || { bad "$backend: render $f: $(cat "$T/err")"; continue; }
    check "$backend: $f: the note names the default light" \
      grep -q "$f: a model alone: lit by the default light, a uniform white background" "$T/err"
    read -r x0 y0 x1 y1 n mx <<< "$(mask "$T/$f.exr")"
    # measured: the cubes cover 21-25 % of the frame, the sphere (4 units
    # tall in a 3.5-unit-wide box) 12 %; the box's bounding sphere keeps
    # every object 3 or more pixels from the border at this size
    num "$n" '>' $((W * H / 12)) && ok || bad "$backend: $f: the object covers $n pixels of $((W * H))"
    num "$x0" '>=' 1 && num "$y0" '>=' 1 && num "$x1" '<=' $((W - 2)) && num "$y1" '<=' $((H - 2)) &&
      ok || bad "$backend: $f: the object's pixels span ($x0 $y0) to ($x1 $y1): not inside the frame"
    # the sky alone lights a white object to at most the sky (3 channels of
    # about 1); the key light adds twice that on the faces it sees
    num "$mx" '>' 3.5 && ok || bad "$backend: $f: brightest pixel $mx: no key light"
  done
  check "$backend: glTF's default material named" \
    grep -q "nomat.gltf: triangles without a material take glTF's default material" "$T/err"
done

# --camera-less framing follows --width/--height: a portrait frame keeps the
# object inside too (the field of view spans the shorter side)
"$BIN" render "$T/cube.glb" --backend cpu --spp 4 --width 32 --height 64 -o "$T/tall.exr" 2>"$T/err" ||
  bad "portrait render: $(cat "$T/err")"
read -r x0 y0 x1 y1 n mx <<< "$(mask "$T/tall.exr")"
num "$x0" '>=' 1 && num "$x1" '<=' 30 && num "$n" '>' 100 && ok ||
  bad "portrait: the object spans x $x0..$x1 ($n pixels)"
# an extension in capitals is a model too; a model that is not one is an error naming it
cp "$T/cube.glb" "$T/CUBE.GLB"
"$BIN" render "$T/CUBE.GLB" --backend cpu --spp 1 --width 8 --height 8 -o "$T/caps.png" 2>"$T/err" &&
  ok || bad "CUBE.GLB: $(cat "$T/err")"
echo "not a model" > "$T/junk.obj"
"$BIN" render "$T/junk.obj" --backend cpu --spp 1 -o "$T/junk.png" > /dev/null 2>"$T/err"; rc=$?
[ $rc -eq 2 ] && grep -q "junk.obj" "$T/err" && [ ! -e "$T/junk.png" ] && ok ||
  bad "junk.obj: exit $rc: $(cat "$T/err")"

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
