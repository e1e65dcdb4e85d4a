#!/usr/bin/env bash
# Normal maps (docs/SCENE_FORMAT.md "Normal maps"), on both backends.
#  ridges: a grey plane (reflectance 0.05) bent by a normal map of 8 facets
#          alternating 20 degrees to -x and +x (a 16-bit PPM written here)
#          against the same ridges made of real triangles, both lit by a
#          distant light from 40 degrees off the vertical towards +x (no
#          facet shadows another: the light is 50 degrees above the plane,
#          the facets 20), seen straight down by an orthographic camera, so
#          each facet covers the same 8 pixel columns in both images. Each
#          facet's mean (its columns but the two at its edges, where the
#          map's bilinear filter blends two facets) must agree within
#          RIDGE_TOL relative; the facets' own radiances differ by 1.9x
#          (cos 60 against cos 20), the unmapped plane's by nothing.
#  flat:   a flat map, (0.5, 0.5, 1) everywhere, gives the image without a
#          map bit for bit: on a flat plane and on a smooth sphere.
#  leak:   tools/gen_meshes.py's leak scenes (a quad before a lit wall, the
#          light between them) with the quad's normals bent 60 degrees by a
#          map instead of its vertex normals: black, for a diffuse, rough
#          and smooth conductor, smooth and rough coating; lit when the light
#          is in front.
source "$(dirname "$0")/lib_cli.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
check "numpy and OpenImageIO importable by $PY (tools/setup.sh)" \
    "$PY" -c "import numpy, OpenImageIO"
# Measured (64 x 32, 64 spp, both backends): the worst facet 0.6 % off, the
# light the real ridges pass between facets, which the map cannot (a V of 140
# degrees sees 6 % of itself, times albedo 0.05, times the other facet's 1.9x
# irradiance; 2 % at albedo 0.2); a map ignored puts facets 23 % and 39 % off.
RIDGE_TOL=0.015

"$PY" - "$T" <<'EOF'
import math, sys
out = sys.argv[1]
th, n = math.radians(20), 8  # facet slope, facets across x -1..1
# the map: 16 texels a facet, 4 rows; c = (m + 1) / 2, rising facets lean -x
with open(out + '/ridge.ppm', 'w') as f:
    f.write('P3 %d 4 65535\n' % (16 * n))
    for r in range(4):
        row = []
        for k in range(n):
            sx = -math.sin(th) if k % 2 == 0 else math.sin(th)
            c = ((sx + 1) / 2, 0.5, (math.cos(th) + 1) / 2)
            row += ['%d %d %d' % tuple(round(65535 * v) for v in c)] * 16
        f.write(' '.join(row) + '\n')
head = ('image 64 32\ncamera position 0 5 0 direction 0 -1 0 up 0 0 -1 orthographic 2\n'
        'spectrum white equal\nlight distant -0.6427876 -0.7660444 0 white 1\n')
quad = 'quad %s -1 0 0.5  1 0 0.5  1 0 -0.5  -1 0 -0.5 uv 0 0 1 0 1 1 0 1\n'
with open(out + '/plane.scene', 'w') as f:
    f.write(head + 'texture ridge ridge.ppm wrap clamp\nmaterial bumpy reflect white 0.05 normal texture ridge\n' + quad % 'bumpy')
with open(out + '/unmapped.scene', 'w') as f:
    f.write(head + 'material grey reflect white 0.05\n' + quad % 'grey')
with open(out + '/ridges.scene', 'w') as f:
    f.write(head + 'material grey reflect white 0.05\n')
    w, h = 2 / n, 2 / n * math.tan(th)
    for k in range(n):
        x0, x1 = -1 + k * w, -1 + (k + 1) * w
        y0, y1 = (0, h) if k % 2 == 0 else (h, 0)
        f.write('quad grey %.9g %.9g 0.5  %.9g %.9g 0.5  %.9g %.9g -0.5  %.9g %.9g -0.5\n'
                % (x0, y0, x1, y1, x1, y1, x0, y0))
EOF
facets() {  # facets EXR: each facet's mean Y over its inner 6 of 8 columns, one a line
  "$PY" - "$1" <<'EOF'
import sys, numpy as np, OpenImageIO as oiio
a = oiio.ImageBuf(sys.argv[1]).get_pixels(oiio.FLOAT)[:, :, :3]
y = a @ np.array([0.2126, 0.7152, 0.0722])
for k in range(8):
    print('%.6f' % y[:, 8 * k + 1:8 * k + 7].mean())
EOF
}
for backend in cpu opencl; do
  for s in plane ridges unmapped; do
    "$BIN" render "$T/$s.scene" --backend $backend --spp 64 --quiet -o "$T/$s-$backend.exr" \
        2>"$T/err" || bad "$backend: render of $s.scene: $(cat "$T/err")"
  done
  mapfile -t P < <(facets "$T/plane-$backend.exr")
  mapfile -t R < <(facets "$T/ridges-$backend.exr")
  mapfile -t U < <(facets "$T/unmapped-$backend.exr")
  [ ${#P[@]} -eq 8 ] && [ ${#R[@]} -eq 8 ] || { bad "$backend: no facet means"; continue; }
  for k in 0 1 2 3 4 5 6 7; do
    tol=$(awk -v r="${R[$k]}" -v t=$RIDGE_TOL 'BEGIN { print r * t }')
    near "${P[$k]}" "${R[$k]}" "$tol" && ok ||
      bad "$backend: facet $k: mapped plane ${P[$k]}, real ridges ${R[$k]} (tolerance $tol)"
  done
  # the ridges show: a facet leaning to the light against one leaning away
  num "$(awk -v a="${R[0]}" -v b="${R[1]}" 'BEGIN { print (a > b ? a / b : b / a) }')" '>' 1.5 && ok ||
    bad "$backend: the real ridges do not show (${R[0]} ${R[1]})"
  near "${U[0]}" "${U[1]}" "$(awk -v r="${U[0]}" 'BEGIN { print 0.01 * r }')" && ok ||
    bad "$backend: the unmapped plane is not uniform (${U[0]} ${U[1]})"
done

# mesh files: the plane as OBJ with 'norm' and with 'map_Bump -bm 1', their
# lifted grey in place of the spectrum: each facet's share of facet 0 as the
# scene format's plane's, within 1 % (the same map, bilinear alike; measured
# equal to 5 digits); as glTF with normalTexture (scale 1); a grey bump image
# is a height map: warned about, the plane flat.
"$PY" - "$T" <<'EOF2'
import base64, json, struct, sys
out = sys.argv[1]
obj = ('mtllib %s.mtl\nv -1 0 0.5\nv 1 0 0.5\nv 1 0 -0.5\nv -1 0 -0.5\n'
       'vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl bumpy\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n')
for name, line in (('norm', 'norm ridge.ppm'), ('bump', 'map_Bump -bm 1 ridge.ppm'),
                   ('grey', 'map_Bump grey.pgm')):
    open('%s/%s.obj' % (out, name), 'w').write(obj % name)
    open('%s/%s.mtl' % (out, name), 'w').write('newmtl bumpy\nKd 0.05 0.05 0.05\n%s\n' % line)
open(out + '/grey.pgm', 'w').write('P2 4 4 255\n' + ' '.join(['0', '255'] * 8) + '\n')
pos = [-1, 0, 0.5, 1, 0, 0.5, 1, 0, -0.5, -1, 0, -0.5]
uv = [0, 1, 1, 1, 1, 0, 0, 0]  # glTF's v runs down the image
idx = [0, 1, 2, 0, 2, 3]
data = struct.pack('<12f8f6H', *pos, *uv, *idx)
g = {'asset': {'version': '2.0'}, 'scene': 0, 'scenes': [{'nodes': [0]}], 'nodes': [{'mesh': 0}],
     'buffers': [{'byteLength': len(data),
                  'uri': 'data:application/octet-stream;base64,' + base64.b64encode(data).decode()}],
     'bufferViews': [{'buffer': 0, 'byteOffset': 0, 'byteLength': 48},
                     {'buffer': 0, 'byteOffset': 48, 'byteLength': 32},
                     {'buffer': 0, 'byteOffset': 80, 'byteLength': 12}],
     'accessors': [{'bufferView': 0, 'componentType': 5126, 'count': 4, 'type': 'VEC3',
                    'min': [-1, 0, -0.5], 'max': [1, 0, 0.5]},
                   {'bufferView': 1, 'componentType': 5126, 'count': 4, 'type': 'VEC2'},
                   {'bufferView': 2, 'componentType': 5123, 'count': 6, 'type': 'SCALAR'}],
     'meshes': [{'primitives': [{'attributes': {'POSITION': 0, 'TEXCOORD_0': 1}, 'indices': 2,
                                 'material': 0}]}],
     'materials': [{'name': 'bumpy', 'normalTexture': {'index': 0, 'scale': 1},
                    'pbrMetallicRoughness': {'baseColorFactor': [0.05, 0.05, 0.05, 1],
                                             'metallicFactor': 0}}],
     'textures': [{'source': 0}], 'images': [{'uri': 'ridge.ppm'}]}
json.dump(g, open(out + '/gl.gltf', 'w'))
EOF2
lit=$(grep '^light' "$T/plane.scene")
for m in norm bump grey gl; do
  f=$m.obj; [ $m = gl ] && f=gl.gltf
  printf 'image 64 32\ncamera position 0 5 0 direction 0 -1 0 up 0 0 -1 orthographic 2\nspectrum white equal\n%s\nmesh %s\n' \
      "$lit" "$f" > "$T/m_$m.scene"
  "$BIN" render "$T/m_$m.scene" --backend cpu --spp 16 --quiet -o "$T/m_$m.exr" 2>"$T/m_$m.err" ||
    bad "render of m_$m.scene: $(cat "$T/m_$m.err")"
done
"$BIN" render "$T/plane.scene" --backend cpu --spp 16 --quiet -o "$T/plane16.exr" 2>"$T/err" ||
  bad "render of plane.scene: $(cat "$T/err")"
mapfile -t P < <(facets "$T/plane16.exr")
for m in norm bump; do
  mapfile -t M < <(facets "$T/m_$m.exr")
  for k in 1 2 3; do
    a=$(awk -v p="${P[$k]}" -v q="${P[0]}" 'BEGIN { print p / q }')
    b=$(awk -v p="${M[$k]:-0}" -v q="${M[0]:-1}" 'BEGIN { print p / q }')
    near "$b" "$a" 0.01 && ok || bad "$m: facet $k at $b of facet 0, the scene format's plane's $a"
  done
done
# glTF's material is a coated base (metallic 0): its facets alternate alike,
# the one leaning from the light the darker
mapfile -t M < <(facets "$T/m_gl.exr")
for k in 2 3; do
  j=$((k - 2))
  near "${M[$k]:-0}" "${M[$j]:-1}" "$(awk -v r="${M[$j]:-1}" 'BEGIN { print 0.01 * r }')" && ok ||
    bad "glTF: facet $k ${M[$k]:-} is not facet $j's ${M[$j]:-}"
done
num "${M[1]:-1}" '<' "$(awk -v r="${M[0]:-0}" 'BEGIN { print 0.75 * r }')" && ok ||
  bad "glTF: the normal texture does not bend the plane (facets ${M[0]:-} ${M[1]:-})"
mapfile -t M < <(facets "$T/m_grey.exr")
near "${M[1]:-0}" "${M[0]:-1}" "$(awk -v r="${M[0]:-1}" 'BEGIN { print 0.01 * r }')" && ok ||
  bad "a grey bump map bends the plane (${M[0]:-} ${M[1]:-})"
check "a grey bump map is warned about: $(cat "$T/m_grey.err")" \
    grep -q "bump map 'grey.pgm' is a grey height map: not rendered" "$T/m_grey.err"

# flat: the map (0.5, 0.5, 1) changes no pixel
python3 "$ROOT/tools/gen_meshes.py" "$T" > /dev/null || { echo "FAIL: gen_meshes.py"; exit 1; }
flat_tex='texture flat checker 1 0.5 0.5 1 0.5 0.5 1'
sed "s/^material grey reflect white 0.05$/$flat_tex\nmaterial grey reflect white 0.05 normal texture flat scale 3/" \
    "$T/unmapped.scene" > "$T/flat.scene"
sed "s/^mesh sphere_n.ply material white smooth/$flat_tex\nmaterial flatw reflect white normal texture flat\nmesh sphere_n.ply material flatw smooth/" \
    "$T/smooth_box.scene" > "$T/flat_sphere.scene"
check "flat_sphere.scene has its map" grep -q "normal texture flat" "$T/flat_sphere.scene"
for backend in cpu opencl; do
  for s in flat unmapped smooth_box flat_sphere; do
    "$BIN" render "$T/$s.scene" --backend $backend --width 48 --height 32 --spp 8 --quiet \
        -o "$T/$s-f-$backend.exr" 2>"$T/err" || bad "$backend: render of $s.scene: $(cat "$T/err")"
  done
  same_pixels "$T/flat-f-$backend.exr" "$T/unmapped-f-$backend.exr" && ok ||
    bad "$backend: a flat normal map changes the plane's image"
  same_pixels "$T/flat_sphere-f-$backend.exr" "$T/smooth_box-f-$backend.exr" && ok ||
    bad "$backend: a flat normal map changes the smooth sphere's image"
done

# leak: the quad of the leak scenes, its normals bent 60 degrees by a map
lean='texture lean checker 1 0.9330127 0.5 0.75 0.9330127 0.5 0.75'
max_sum() {  # max_sum EXR: the image's largest R + G + B of a pixel's maxima
  oiiotool "$1" --printstats 2>/dev/null |
    awk -F: '/Stats Max/ { split($2, v, " "); print v[1] + v[2] + v[3]; exit }'
}
quad='quad QM -10 -10 0  10 -10 0  10 10 0  -10 10 0 uv 0 0 1 0 1 1 0 1'
for name in leak leak_lit; do
  for kind in diffuse rough mirror paint satin; do
    mat=$(awk '/^mesh tilt.obj/ { print $4 }' "$T/${name}_$kind.scene")
    { echo "$lean"; sed -e "s/^material $mat \(.*\)$/material $mat \1\nmaterial bent \1 normal texture lean/" \
        -e "s/^mesh tilt.obj .*/${quad/QM/bent}/" "$T/${name}_$kind.scene"; } > "$T/n${name}_$kind.scene"
  done
done
for backend in cpu opencl; do
  for kind in diffuse rough mirror paint satin; do
    "$BIN" render "$T/nleak_$kind.scene" --backend $backend --spp 64 --quiet \
        -o "$T/nleak_$kind-$backend.exr" 2>"$T/err" ||
      bad "$backend: render of nleak_$kind.scene: $(cat "$T/err")"
    m=$(max_sum "$T/nleak_$kind-$backend.exr")
    num "$m" == 0 && ok || bad "$backend: $kind: light leaks through the mapped quad: max $m"
    [ "$kind" = mirror ] && continue # its mirror direction lies at the horizon: nothing there
    "$BIN" render "$T/nleak_lit_$kind.scene" --backend $backend --spp 64 --quiet \
        -o "$T/nlit_$kind-$backend.exr" 2>"$T/err" ||
      bad "$backend: render of nleak_lit_$kind.scene: $(cat "$T/err")"
    m=$(max_sum "$T/nlit_$kind-$backend.exr")
    num "$m" '>' 0.1 && ok || bad "$backend: $kind: the mapped quad lit from the front is black: max $m"
  done
done
finish
