#!/usr/bin/env bash
# A mesh file's texture coordinates reach its triangles: a quad of two
# triangles as an OBJ with an MTL whose map_Kd is an 8-bit sRGB PNG of 4 x 4
# blocks of 16 colours (Kd 1, no Ks: a Lambertian reflectance, textured per
# point), and the same quad as a glTF (TEXCOORD_0 in a data-URI buffer, glTF's
# top-left origin) and as a binary PLY (its vertices' s t) under a scene material
# `reflect texture` of the same PNG,
# fill an orthographic view under a uniform D65 sky of luminance 1, so each
# block's linear sRGB is its decoded texel's (as tests/cli_texture_quad.sh:
# per block, its middle half, within CIEDE2000 1, white Y = 1), on both
# backends in `ml` (the levels) and `truth`. Texture coordinates dropped on
# the wire, read upside down or in the wrong winding, or the map_Kd image not
# bound move blocks by far more (neighbouring blocks differ by dE00 > 10).
# colour-science and OpenImageIO's Python module: tools/setup.sh
# (build/pyenv); SPECMIP_PYTHON names another interpreter.
source "$(dirname "$0")/lib_cli.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
check "colour-science and OpenImageIO importable by $PY (tools/setup.sh)" \
    "$PY" -c "import colour, OpenImageIO"

"$PY" "$ROOT/tests/texture_blocks.py" write "$T/blocks.png" || bad "no texture written"
"$PY" - "$T" << 'PYEOF' || bad "no model written"
import base64, json, struct, sys
d = sys.argv[1]
# the quad (-1 -1 0) (1 -1 0) (1 1 0) (-1 1 0), (u, v) its unit square, v up
p = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
with open(d + "/quad.mtl", "w") as f:
    f.write("newmtl board\nKd 1 1 1\nKs 0 0 0\nmap_Kd blocks.png\n")
with open(d + "/quad.obj", "w") as f:
    f.write("mtllib quad.mtl\n")
    f.writelines("v %g %g %g\n" % q for q in p)
    f.writelines("vt %g %g\n" % t for t in uv)
    f.write("usemtl board\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
# glTF: TEXCOORD_0's t runs down from the image's top (t = 1 - v)
pos = b"".join(struct.pack("<3f", *q) for q in p)
tex = b"".join(struct.pack("<2f", u, 1 - v) for u, v in uv)
idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
buf = pos + tex + idx
gltf = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                    "indices": 2}]}],
        "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64,"
                     + base64.b64encode(buf).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                        {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [-1, -1, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                      {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]}
json.dump(gltf, open(d + "/quad.gltf", "w"))
# PLY, binary: a vertex's s t after its x y z, then a property not read
with open(d + "/quad.ply", "wb") as f:
    f.write(b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
            b"property float y\nproperty float z\nproperty float s\nproperty float t\n"
            b"property uchar flag\nelement face 2\nproperty list uchar int vertex_indices\n"
            b"end_header\n")
    f.write(b"".join(struct.pack("<5fB", *(q + t + (7,))) for q, t in zip(p, uv)))
    f.write(struct.pack("<B3iB3i", 3, 0, 1, 2, 3, 0, 2, 3))
PYEOF
common='image 32 32
spp 512
camera position 0 0 -2  direction 0 0 1  orthographic 2
spectrum d65 file illuminant_D65.csv
background both d65 1'
printf '%s\nmesh quad.obj\n' "$common" > "$T/obj.scene"
printf '%s\ntexture blocks blocks.png\nmaterial board reflect texture blocks\nmesh quad.gltf material board\n' \
    "$common" > "$T/gltf.scene"
sed 's/quad.gltf/quad.ply/' "$T/gltf.scene" > "$T/ply.scene"
for model in obj gltf ply; do
  for backend in opencl cpu; do
    for mode in truth ml; do
      "$BIN" render "$T/$model.scene" --backend $backend --mode $mode --seed 5 \
        -o "$T/$model-$backend-$mode.exr" > /dev/null 2>"$T/err" ||
        { bad "$model $backend $mode: $(cat "$T/err")"; continue; }
      if [ $model = obj ]; then
        check "$model $backend $mode: no mean-colour warning: $(cat "$T/err")" \
          bash -c "! grep -q 'mean colour' '$T/err'"
      fi
      "$PY" "$ROOT/tests/texture_blocks.py" "$T/blocks.png" "$T/$model-$backend-$mode.exr" > "$T/py" 2>&1
      rc=$?
      check "$model $backend $mode: every block within dE00 1 of its texel: $(tail -3 "$T/py")" \
        test $rc -eq 0
      echo "$model $backend $mode $(tail -1 "$T/py")"
    done
  done
done
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
