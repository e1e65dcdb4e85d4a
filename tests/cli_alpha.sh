#!/usr/bin/env bash
# Opacity in traversal (docs/SCENE_FORMAT.md "Opacity"), on both backends.
# The mask: 8 x 8 texels, the left four columns 0 and the right four 1 (a
# PGM written here), clamped, cut at 0.5: its bilinear value crosses 0.5
# exactly at u = 1/2, so the cut falls on a pixel edge of a 32-pixel view.
#  cover:  a green board filling an orthographic view under a uniform white
#          sky: the columns where the mask is 0 show the sky, exactly 1 in
#          every channel (rays that escape); the others the board (red under
#          0.5: its reflectance is 0.05 in the red). With 'opacity 0.25 blend'
#          the sky's share of the image is 1 - 0.25 = 0.75: the red channel's
#          mean is 0.75 + 0.25 B (B the board's mean red, from the cut-out
#          render), within 0.02 (the estimate's standard deviation over
#          16384 binary decisions is 0.0034).
#  shadow: the board 1 above a grey floor (reflectance 0.5), lit by a
#          distant light along (1, -1, 0) of irradiance 1, seen from above: x
#          0..2 across the image. Its shadow falls at x + 1: the floor is lit
#          where the mask is 0 (x 0..0.5 seen through the board, x 1..1.5)
#          at the closed form 0.5 cos 45 / pi = 0.1125 (within 10 %, the
#          board's underside adds a little), and dark (under 0.02) at x 1.5..2,
#          under the mask's 1s; the board shows green at x 0.5..1.
# Every pixel is checked, so a cut one texel off fails.
source "$(dirname "$0")/lib_cli.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
check "numpy and OpenImageIO importable by $PY (tools/setup.sh)" \
    "$PY" -c "import numpy, OpenImageIO"

{ echo "P2 8 8 255"; for r in 1 2 3 4 5 6 7 8; do echo "0 0 0 0 255 255 255 255"; done; } > "$T/mask.pgm"
head_lines='spectrum d65 file illuminant_D65.csv
spectrum green inline 380 0.05 500 0.05 520 0.8 580 0.8 600 0.05 780 0.05 end
texture mask mask.pgm wrap clamp'
for kind in cut blend; do
  opacity="opacity texture mask"
  [ $kind = blend ] && opacity="opacity 0.25 blend"
  cat > "$T/cover-$kind.scene" <<SCENE
image 32 32
spp 16
camera position 0 0 -2  direction 0 0 1  orthographic 2
$head_lines
material board reflect green $opacity
quad board  -1 -1 0  1 -1 0  1 1 0  -1 1 0
background both d65 1
SCENE
done
sed -i 's/^texture mask/#/' "$T/cover-blend.scene"
cat > "$T/shadow.scene" <<SCENE
image 32 16
spp 16
camera position 1 5 0.5  direction 0 -1 0  up 0 0 1  orthographic 2
$head_lines
spectrum grey inline 380 0.5 780 0.5 end
material board reflect green opacity texture mask
material floor reflect grey
quad board  0 1 0  1 1 0  1 1 1  0 1 1
quad floor  -5 0 -5  -5 0 5  5 0 5  5 0 -5
light distant 1 -1 0 d65 1
SCENE

# The same quad from mesh files: an OBJ whose MTL has map_d (the mask; MTL's
# dissolve is stochastic opacity, so where the bilinear value runs between 0
# and 1 — a texel wide about the middle, columns 14 to 17, and about the
# edges, where a mesh's map repeats, columns 0, 1, 30 and 31 — a pixel may
# show either), and a glTF whose baseColorTexture's alpha channel is the
# mask, alphaMode MASK, cut at 0.5: exactly the scene's quad (its
# occlusionTexture is warned about by name).
"$PY" - "$T" << 'PYEOF' || bad "no models written"
import base64, json, struct, sys, numpy as np, OpenImageIO as oiio
d = sys.argv[1]
a = np.zeros((8, 8, 4), np.uint8); a[:, :, :3] = 255; a[:, 4:, 3] = 255
out = oiio.ImageOutput.create(d + "/rgba.png")
out.open(d + "/rgba.png", oiio.ImageSpec(8, 8, 4, "uint8")); out.write_image(a); out.close()
p = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
uv = [(0, 0), (1, 0), (1, 1), (0, 1)]
with open(d + "/quad.mtl", "w") as f:
    f.write("newmtl board\nKd 0.05 0.6 0.05\nKs 0 0 0\nmap_d mask.pgm\n")
with open(d + "/quad.obj", "w") as f:
    f.write("mtllib quad.mtl\n")
    f.writelines("v %g %g %g\n" % q for q in p)
    f.writelines("vt %g %g\n" % t for t in uv)
    f.write("usemtl board\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
pos = b"".join(struct.pack("<3f", *q) for q in p)
tex = b"".join(struct.pack("<2f", u, 1 - v) for u, v in uv)
buf = pos + tex + struct.pack("<6H", 0, 1, 2, 0, 2, 3)
gltf = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2,
                                    "material": 0}]}],
        "materials": [{"name": "board", "alphaMode": "MASK", "alphaCutoff": 0.5,
                       "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.6, 0.05, 1],
                                                "baseColorTexture": {"index": 0},
                                                "metallicFactor": 0, "roughnessFactor": 1},
                       "occlusionTexture": {"index": 0}}],
        "textures": [{"source": 0}], "images": [{"uri": "rgba.png"}],
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
PYEOF
for f in obj gltf; do
  sed -e '/^material board/d' -e "s/^quad board.*/mesh quad.$f/" -e '/^texture mask/d' -e '/green/d' \
    "$T/cover-cut.scene" > "$T/cover-$f.scene"
done

cat > "$T/check.py" <<'PY'
import sys, numpy as np, OpenImageIO as oiio
def img(p):
    return oiio.ImageBuf(p).get_pixels(oiio.FLOAT)[:, :, :3]
what, errs = sys.argv[1], []
if what == "cover":
    a = img(sys.argv[2]); r = a[:, :, 0]
    seam = int(sys.argv[3]) if len(sys.argv) > 3 else 0
    sky, board = r[:, seam:16 - seam], r[:, 16 + seam:32 - seam]
    if not np.all(np.abs(a[:, seam:16 - seam] - 1.0) < 1e-3): errs.append("mask-0 columns not all sky: min red %.3f" % sky.min())
    if not np.all(board < 0.5): errs.append("mask-1 columns not all board: max red %.3f" % board.max())
    print("sky columns red %.4f..%.4f, board columns red %.4f..%.4f" % (sky.min(), sky.max(), board.min(), board.max()))
elif what == "blend":
    cut, bl = img(sys.argv[2]), img(sys.argv[3])
    b = cut[:, 16:, 0].mean(); want = 0.75 + 0.25 * b; got = bl[:, :, 0].mean()
    print("blend 0.25: red mean %.4f, closed form %.4f (board red %.4f)" % (got, want, b))
    if abs(got - want) > 0.02: errs.append("sky share off")
else:
    a = img(sys.argv[2]); r, g = a[:, :, 0], a[:, :, 1]
    lit = np.concatenate([r[:, 0:8], r[:, 16:24]], axis=1); dark = r[:, 24:32]; leaf = a[:, 8:16]
    want = 0.5 * np.cos(np.pi / 4) / np.pi
    print("lit %.4f..%.4f (closed form %.4f), shadow max %.4f, board green/red min %.2f" %
          (lit.min(), lit.max(), want, dark.max(), (leaf[:, :, 1] / np.maximum(leaf[:, :, 0], 1e-6)).min()))
    if not np.all(np.abs(lit / want - 1) < 0.1): errs.append("floor not lit where the mask is 0")
    if not np.all(dark < 0.02): errs.append("floor not in shadow where the mask is 1")
    if not np.all(leaf[:, :, 1] > 3 * leaf[:, :, 0]): errs.append("board not seen where the mask is 1")
for e in errs: print("  " + e)
sys.exit(1 if errs else 0)
PY

for backend in opencl cpu; do
  for s in cover-cut cover-blend shadow cover-obj cover-gltf; do
    "$BIN" render "$T/$s.scene" --backend $backend --mode rgb --seed 3 --quiet -o "$T/$backend-$s.exr" \
      2>"$T/err" || bad "$backend $s: $(cat "$T/err")"
    if [ $s = cover-gltf ]; then
      grep -q "occlusion maps" "$T/err" && ok ||
        bad "$backend: the glTF's occlusion map not warned about by name: $(cat "$T/err")"
    fi
  done
  for c in "cover:the sky exactly where the mask is 0:cover-cut" \
           "blend:stochastic opacity 0.25:cover-cut cover-blend" \
           "shadow:shadows only where the mask is 1:shadow" \
           "cover:OBJ map_d:cover-obj 2" "cover:glTF alphaMode MASK:cover-gltf"; do
    IFS=: read -r what title imgs <<< "$c"
    args=()
    for i in $imgs; do [[ $i = [0-9] ]] && args+=("$i") || args+=("$T/$backend-$i.exr"); done
    "$PY" "$T/check.py" "$what" "${args[@]}" > "$T/py" 2>&1
    rc=$?
    check "$backend: $title: $(cat "$T/py")" test $rc -eq 0
    echo "$backend: $(cat "$T/py")"
  done
done
# bad input: an error naming the file, line and problem, exit 2
for bad_clause in "opacity texture nosuch:unknown texture 'nosuch'" "opacity 2:an opacity (0 to 1)" \
                  "opacity texture mask cutoff -1:an opacity cutoff (0 to 1)"; do
  sed "s/^material board reflect green.*/material board reflect green ${bad_clause%%:*}/" \
    "$T/cover-cut.scene" > "$T/bad.scene"
  "$BIN" render "$T/bad.scene" --backend cpu --quiet -o "$T/bad.exr" 2> "$T/err"
  rc=$?
  check "'${bad_clause%%:*}': exit 2 naming bad.scene:7 and '${bad_clause#*:}': $(cat "$T/err")" \
    bash -c "[ $rc -eq 2 ] && grep -q 'bad.scene:7:' '$T/err' && grep -qF -- \"${bad_clause#*:}\" '$T/err'"
done
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
