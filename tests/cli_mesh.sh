#!/bin/bash
# The mesh statement from the command line: an emissive glTF quad lights the
# scene through its front face only (the winding decides); the README's mesh
# example renders; bad mesh input exits 2 naming the file with nothing
# written; Ctrl-C while the importer runs exits 130 and leaves no child.
# usage: bash tests/cli_mesh.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
python3 "$ROOT/tools/gen_meshes.py" "$T" || { echo "FAIL: gen_meshes.py"; exit 1; }
R=(--backend cpu)  # not --quiet: the mesh notes (triangles, box) are checked
avg() {  # avg IMAGE WxH+X+Y: mean of the region's first channel
    oiiotool "$1" --cut "$2" --printstats | awk '/Stats Avg/ { print $3 }'
}
above() { num "$1" '>' "$2"; }
not_said() { ! grep -q "$1" "$T/err"; }

# 1. The quad faces the camera (-z): the centre sees its emission and the floor
#    in front of it is lit. Turned round, the camera sees its black back and the
#    floor between them gets nothing.
cat > "$T/quad.scene" << 'S'
image 16 16
camera position 0 0 -4 direction 0 0 1 fov 60
spectrum white equal
material floor reflect white 0.8
quad floor -3 -1 -3  -3 -1 3  3 -1 3  3 -1 -3
S
cp "$T/quad.scene" "$T/back.scene"
echo "mesh quad_emit.gltf" >> "$T/quad.scene"
echo "mesh quad_emit.gltf rotate 0 1 0 180" >> "$T/back.scene"
"$BIN" render "$T/quad.scene" "${R[@]}" --spp 16 -o "$T/front.exr" 2> "$T/err"
check "front: renders" test $? -eq 0
check "front: prints the triangle count and box" \
    grep -q "quad_emit.gltf: 2 triangles, bounding box (-1 -1 0) to (1 1 0)" "$T/err"
check "front: the quad is seen emitting" above "$(avg "$T/front.exr" 2x2+7+7)" 0.5
check "front: the floor is lit" above "$(avg "$T/front.exr" 16x3+0+13)" 0.01
"$BIN" render "$T/back.scene" "${R[@]}" --spp 16 -o "$T/back.exr" 2> /dev/null
check "back: renders" test $? -eq 0
check "back: the quad's back is black" num "$(avg "$T/back.exr" 2x2+7+7)" == 0
check "back: the floor before it is dark" num "$(avg "$T/back.exr" 16x3+0+13)" == 0

# A glTF emissive strength (KHR_materials_emissive_strength, read from the
# JSON: Assimp 5.2 drops it) multiplies the emission: 5 makes the quad seen
# directly 5 times as bright (the same paths: exactly, up to float rounding);
# a negative one is ignored with a warning.
strength() { # strength VALUE: strength.scene with the quad's strength VALUE
  python3 -c 'import json, sys; d = json.load(open(sys.argv[1]))
d["materials"][0]["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": float(sys.argv[3])}}
json.dump(d, open(sys.argv[2], "w"))' "$T/quad_emit.gltf" "$T/strength.gltf" "$1"
  sed 's/quad_emit.gltf/strength.gltf/' "$T/quad.scene" > "$T/strength.scene"
}
strength 5
"$BIN" render "$T/strength.scene" "${R[@]}" --spp 16 -o "$T/s.exr" 2> "$T/err"
check "emissive strength: renders" test $? -eq 0
check "emissive strength: not warned" not_said "KHR_materials_emissive_strength"
check "emissive strength 5: the quad 5 times as bright" \
    num "$(awk -v a="$(avg "$T/s.exr" 2x2+7+7)" -v b="$(avg "$T/front.exr" 2x2+7+7)" \
      'BEGIN { d = a / (5 * b) - 1; print d < 0 ? -d : d }')" '<' 1e-4
strength -1
"$BIN" render "$T/strength.scene" "${R[@]}" --spp 1 -o "$T/s.exr" 2> "$T/err"
check "emissive strength -1: renders" test $? -eq 0
check "emissive strength -1: warned" grep -q "warning: .*KHR_materials_emissive_strength" "$T/err"

# Glass on an open mesh is warned about with its count of unpaired edges (the
# quad: 4); on a closed one (the bundled sphere) it is not.
cp "$ROOT/scenes/materials_sphere.ply" "$T/"
for m in quad_emit.gltf materials_sphere.ply; do
    { sed '$d' "$T/quad.scene"; echo "material lamp emit white 10"
      echo "quad lamp -1 3 -1  1 3 -1  1 3 1  -1 3 1"; echo "material glass dielectric ior 1.5"
      echo "mesh $m material glass"; } > "$T/glass.scene"
    "$BIN" render "$T/glass.scene" "${R[@]}" --spp 1 -o "$T/s.exr" 2> "$T/err-$m"
    rc=$?
    check "glass on $m: renders ($(head -c 300 "$T/err-$m"))" test $rc -eq 0
done
check "open glass: warned ($(grep -i 'not closed' "$T/err-quad_emit.gltf"))" grep -q \
    "'quad_emit.gltf': its glass ('glass', 2 triangles) is not closed: 4 edges" "$T/err-quad_emit.gltf"
check "closed glass: not warned" eval "! grep -q 'not closed' '$T/err-materials_sphere.ply'"

# Every glTF extension the file uses and specmip does not render is named
# (Assimp hides those it does not read); the ones it renders are not.
python3 -c 'import json, sys; d = json.load(open(sys.argv[1]))
d["extensionsUsed"] = ["KHR_materials_clearcoat", "KHR_materials_ior", "KHR_materials_sheen", "EXT_made_up"]
json.dump(d, open(sys.argv[2], "w"))' "$T/quad_emit.gltf" "$T/ext.gltf"
sed 's/quad_emit.gltf/ext.gltf/' "$T/quad.scene" > "$T/ext.scene"
"$BIN" render "$T/ext.scene" "${R[@]}" --spp 1 -o "$T/s.exr" 2> "$T/err"
check "extensions: renders" test $? -eq 0
check "extensions: each one not rendered named ($(grep extension "$T/err"))" grep -q \
    "ext.gltf: glTF extensions KHR_materials_clearcoat, KHR_materials_sheen, EXT_made_up not rendered" "$T/err"
check "extensions: a rendered one not named" eval "! grep -q KHR_materials_ior \"$T/err\""

# 2. The README's mesh example (the first block with a mesh statement).
awk '/^```/ { if (b) { if (m) { printf "%s", buf; exit } b = 0; buf = ""; m = 0; next } b = 1; next }
     b { buf = buf $0 "\n"; if ($1 == "mesh") m = 1 }' "$ROOT/README.md" > "$T/room.scene"
check "README has a mesh example" grep -q '^mesh' "$T/room.scene"
check "README mesh example renders" "$BIN" render "$T/room.scene" "${R[@]}" --spp 1 --width 16 \
    --height 12 -o "$T/room.exr"

# 3. Bad input: exit 2, the file named, nothing written.
refused() {  # refused NAME STATEMENT EXPECTED-TEXT
    sed '$d' "$T/quad.scene" > "$T/$1.scene"
    echo "$2" >> "$T/$1.scene"
    rm -f "$T/out.exr"
    "$BIN" render "$T/$1.scene" "${R[@]}" --spp 1 -o "$T/out.exr" 2> "$T/err"
    local rc=$?
    check "$1: exit 2 (got $rc)" test $rc -eq 2
    check "$1: says '$3'" grep -q -- "$3" "$T/err"
    check "$1: nothing written" test ! -e "$T/out.exr"
}
printf 'solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n' > "$T/cut.stl"
head -c 300 "$T/cube.glb" > "$T/cut.glb"
head -c 400 "$T/cube_binary.ply" > "$T/cut.ply"  # Assimp 5.2 crashed on it; the own reader says where it ends
refused missing "mesh nosuch.obj" "mesh file 'nosuch.obj' not found"
refused format "mesh quad.scene" "unknown format"
refused garbage "mesh cut.glb" "cut.glb"
refused truncated "mesh cut.stl material floor" "cut.stl"
refused cut_ply "mesh cut.ply material floor" "cut.ply: element face item 8 (byte 399): the file ends before the element's 12 items"
refused nomaterial "mesh cube_ascii.stl" "cube_ascii.stl has triangles without a material"
refused unbound "mesh cube.obj bind blue floor" "cube.obj has no material 'blue' (it has 'red', 'white')"
refused unknown "mesh cube.obj material paint" "unknown material 'paint'"
refused zeroscale "mesh cube.obj scale 1 0 1" "a scale must not be zero"
refused axis "mesh cube.obj rotate 0 0 0 10" "the rotation axis must be a non-zero vector"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2 7\n' > "$T/badstrip.ply"
refused badstrip "mesh badstrip.ply material floor" "badstrip.ply:13: element tristrips item 1: vertex index 7 is out of range"
refused twice "mesh cube.obj material floor material floor" "expected 'material' (once), 'bind'"
SPECMIP_TEST_MESH_CHILD=crash refused crash "mesh cube.obj" "cube.obj: the importer crashed"

# PLY triangle strips, read by the project's own code: the cube's 12 triangles.
sed '$d' "$T/quad.scene" > "$T/strips.scene"
printf 'background both white 1\nmesh cube_strips.ply material floor translate -1 -1 0\n' >> "$T/strips.scene"
"$BIN" render "$T/strips.scene" "${R[@]}" --spp 4 -o "$T/strips.exr" 2> "$T/err"
check "strips: renders" test $? -eq 0
check "strips: the cube's 12 triangles and box" \
    grep -q "cube_strips.ply: 12 triangles, bounding box (-1 -1 0) to (1 1 2)" "$T/err"
# the background alone gives 1 there; the cube's face (reflectance 0.8) less
check "strips: the cube is seen" num "$(avg "$T/strips.exr" 2x2+7+7)" '<' 0.9

# Transforms apply in the order written: scale 2 then translate 1 0 0 puts the
# quad's (-1 -1 0) to (1 1 0) at (-1 -2 0) to (3 2 0); the other order at
# (0 -2 0) to (4 2 0); two rotations of one mesh are allowed.
box_of() {  # box_of CLAUSES: the bounding box the mesh statement prints
    sed '$d' "$T/quad.scene" > "$T/order.scene"
    echo "mesh quad_emit.gltf $1" >> "$T/order.scene"
    "$BIN" render "$T/order.scene" --backend cpu --spp 1 -o "$T/order.exr" 2> "$T/err" || echo "render failed"
    sed -n 's/.*quad_emit.gltf: 2 triangles, bounding box //p' "$T/err"
}
check "order: scale then translate" test "$(box_of 'scale 2 translate 1 0 0')" = "(-1 -2 0) to (3 2 0)"
check "order: translate then scale" test "$(box_of 'translate 1 0 0 scale 2')" = "(0 -2 0) to (4 2 0)"
check "order: scale, translate, scale" test "$(box_of 'scale 2 translate 1 0 0 scale 0.5')" = \
    "(-0.5 -1 0) to (1.5 1 0)"
check "order: two rotations accepted" test -n "$(box_of 'rotate 1 0 0 -90 rotate 0 1 0 180')"

# COLLADA through Assimp: a two-triangle quad with its material, as the glTF quad.
cat > "$T/quad.dae" << 'D'
<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_effects><effect id="e"><profile_COMMON><technique sid="t"><lambert>
    <diffuse><color>0.8 0.2 0.2 1</color></diffuse></lambert></technique></profile_COMMON></effect></library_effects>
  <library_materials><material id="red" name="red"><instance_effect url="#e"/></material></library_materials>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="12">-1 -1 0 1 -1 0 1 1 0 -1 1 0</float_array>
      <technique_common><accessor source="#pa" count="4" stride="3"><param name="X" type="float"/>
      <param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles material="red" count="2"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2 0 2 3</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n"><instance_geometry url="#g"><bind_material>
    <technique_common><instance_material symbol="red" target="#red"/></technique_common></bind_material>
  </instance_geometry></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
D
sed '$d' "$T/quad.scene" > "$T/dae.scene"
printf 'background both white 1\nmesh quad.dae\n' >> "$T/dae.scene"
"$BIN" render "$T/dae.scene" "${R[@]}" --spp 4 -o "$T/dae.exr" 2> "$T/err"
check "COLLADA: renders" test $? -eq 0
check "COLLADA: its two triangles and box" \
    grep -q "quad.dae: 2 triangles, bounding box (-1 -1 0) to (1 1 0)" "$T/err"
check "COLLADA: the red quad is seen" above "$(avg "$T/dae.exr" 2x2+7+7)" 0.01

# An OBJ whose MTL file is missing: a warning naming it, and its materials are
# no materials (Assimp would make them its default grey): without a clause the
# load fails as for a mesh without materials, with one it renders. An OBJ whose
# MTL is there gets no such warning. Features ignored (here vertex normals, in
# two meshes) are said once per run.
sed 's/^mtllib cube.mtl/mtllib cube_missing.mtl/' "$T/cube.obj" > "$T/nomtl.obj"
check "OBJ without its MTL made" grep -q '^mtllib cube_missing.mtl' "$T/nomtl.obj"
refused nomtl "mesh nomtl.obj" "nomtl.obj has triangles without a material"
check "missing MTL: named in a warning" \
    grep -q "warning: .*nomtl.obj: MTL file 'cube_missing.mtl' not found beside it; without it these have no material: 'red', 'white'" "$T/err"
cp "$T/quad.scene" "$T/nomtl.scene"
echo "mesh nomtl.obj material floor translate 0 0 5" >> "$T/nomtl.scene"
"$BIN" render "$T/nomtl.scene" "${R[@]}" --spp 1 -o "$T/nomtl.exr" 2> "$T/err"
check "missing MTL, 'material': renders" test $? -eq 0
check "missing MTL, 'material': still warned" grep -q "MTL file 'cube_missing.mtl' not found" "$T/err"
cp "$T/quad.scene" "$T/mtl.scene"
echo "mesh cube.obj translate 0 0 5" >> "$T/mtl.scene"
"$BIN" render "$T/mtl.scene" "${R[@]}" --spp 1 -o "$T/mtl.exr" 2> "$T/err"
check "MTL present: renders" test $? -eq 0
check "MTL present: no MTL warning" not_said "MTL file"
awk 'NR == 1 { print "vn 0 0 1" } /^f / { printf "f"; for (i = 2; i <= NF; i++) printf " %s//1", $i; print ""; next }
     { print }' "$T/cube.obj" > "$T/normals.obj"
check "OBJ with vertex normals made" grep -q '^vn ' "$T/normals.obj"
cp "$T/quad.scene" "$T/normals.scene"
printf 'mesh normals.obj translate 0 0 5\nmesh normals.obj translate 2 0 5\n' >> "$T/normals.scene"
"$BIN" render "$T/normals.scene" "${R[@]}" --spp 1 -o "$T/normals.exr" 2> "$T/err"
check "two meshes with normals: renders" test $? -eq 0
check "vertex normals ignored: said once ($(grep -c 'vertex normals ignored' "$T/err") times)" \
    test "$(grep -c 'vertex normals ignored' "$T/err")" -eq 1

# A base-colour texture: its mean colour times the factor, and a warning that
# says so with the mean (tex.mean: 0.447 0.381 0.193); bound to a scene
# material instead, nothing is said.
cp "$T/quad.scene" "$T/tex.scene"
echo "mesh tex_cube.glb translate 0 0 5" >> "$T/tex.scene"
"$BIN" render "$T/tex.scene" "${R[@]}" --spp 1 -o "$T/tex.exr" 2> "$T/err"
check "textured glb: renders" test $? -eq 0
check "textured glb: the mean colour is said" grep -q "warning: .*tex_cube.glb: material 'red': base-colour texture 'embedded image 0' replaced by its mean colour (0.447 0.381 0.193, linear) times the material's colour" "$T/err"
check "textured glb: not as a texture ignored" not_said "textures ignored"
cp "$T/quad.scene" "$T/texbound.scene"
echo "mesh tex_cube.gltf material floor translate 0 0 5" >> "$T/texbound.scene"
"$BIN" render "$T/texbound.scene" "${R[@]}" --spp 1 -o "$T/tex.exr" 2> "$T/err"
check "textured glTF bound: renders" test $? -eq 0
check "textured glTF bound: no texture warning" not_said "base-colour texture"
sed 's/tex.png/nosuch.png/' "$T/tex_cube.mtl" > "$T/notex.mtl"
sed 's/tex_cube.mtl/notex.mtl/' "$T/tex_cube.obj" > "$T/notex.obj"
cp "$T/quad.scene" "$T/notex.scene"
echo "mesh notex.obj translate 0 0 5" >> "$T/notex.scene"
"$BIN" render "$T/notex.scene" "${R[@]}" --spp 1 -o "$T/tex.exr" 2> "$T/err"
check "missing texture: renders" test $? -eq 0
check "missing texture: said, the colour alone used" grep -q "notex.obj: material 'red': base-colour texture 'nosuch.png' cannot be read (no such file beside the model): the material's colour alone is used" "$T/err"

# 4. Ctrl-C while the importer runs (a child that never answers; the parent
#    held at the "mesh" test pause): exit 130 within a few seconds, nothing
#    written, the child killed.
rm -f "$T/out.exr"
SPECMIP_TEST_MESH_CHILD=hang SPECMIP_TEST_PAUSE=mesh "$BIN" render "$T/quad.scene" "${R[@]}" \
    -o "$T/out.exr" 2> "$T/err" &
pid=$!
for i in $(seq 600); do grep -q "test pause at mesh" "$T/err" && break; sleep 0.1; done
child=$(ps -o pid= --ppid $pid | tr -d ' ' | head -n 1)
check "interrupt: the importer runs at the pause" test -n "$child" -a -e "/proc/$child"
kill -INT $pid
for i in $(seq 100); do kill -0 $pid 2> /dev/null || break; sleep 0.1; done  # 10 s: generous
kill -0 $pid 2> /dev/null && { bad "interrupt: still running 10 s after the signal"; kill -9 $pid; }
wait $pid
rc=$?
check "interrupt: exit 130 (got $rc)" test $rc -eq 130
check "interrupt: says so" grep -q "interrupted while loading .*quad_emit.gltf" "$T/err"
check "interrupt: nothing written" test ! -e "$T/out.exr"
check "interrupt: the importer is gone" test ! -e "/proc/$child"
finish
