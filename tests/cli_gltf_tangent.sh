#!/usr/bin/env bash
# The tangent frame a glTF normal map bends the normal in (spm_shared.h
# SPM_NMAP_*), on both backends. A plane (y = 0, normal +y) whose map is one
# tilt everywhere, so that the frame alone decides where the normal leans,
# lit by a distant light 40 degrees off the vertical from the side the frame
# should lean the normal to (the lit side's radiance goes as cos 20 = 0.94;
# a frame turned a quarter, or mirrored, leans it across: cos 40 cos 20 =
# 0.72, or away: cos 60 = 0.5), the image's mean against a peer's:
# 1. TANGENT from the file: `file` gives uvs with dP/du = +x, dP/dv = +z but
#    TANGENT +z with w = -1 (bitangent w (N x T) = -x); the map leans 20
#    degrees to (T + B) / sqrt 2 = (z - x) / sqrt 2. Its peer `made` has no
#    TANGENT and uvs with dP/du = +z, dP/dv = -x, whose made frame is the
#    file's. `ignored` is `file` without TANGENT: the made frame leans the
#    normal to (x + z) / sqrt 2, across the light (must differ: a test that
#    could not see TANGENT ignored would pass on it).
# 2. A quarter turn of KHR_texture_transform: `turned` (dP/du = +x,
#    dP/dv = -z, rotation pi/2) reads a map leaning to +u' (tangent-space
#    (sin 20, 0, cos 20)); +u' = +v_glTF runs along -dP/dv = +z on the plane.
#    Its peer `preturned` has no transform and the map turned on disk, the
#    same normal in the untransformed frame: (0, -sin 20, cos 20).
# Measured (32 x 32, 16 spp, same seed): each peer equal to 6 digits;
# `ignored` 23 % off `made`, the turn without the frame's turn 23 % off.
source "$(dirname "$0")/lib_cli.sh"
TOL=0.01
python3 - "$T" <<'PYEOF'
import base64, json, math, struct, sys
out = sys.argv[1]
th = math.radians(20)
s, c = math.sin(th), math.cos(th)
def ppm(name, m):  # a 4 x 4 map of one tangent-space normal m, 16 bits
    code = ' '.join('%d' % round(65535 * (v + 1) / 2) for v in m)
    open('%s/%s.ppm' % (out, name), 'w').write('P3 4 4 65535\n' + ' '.join([code] * 16) + '\n')
ppm('lean_tb', (s / math.sqrt(2), s / math.sqrt(2), c))
ppm('lean_u', (s, 0, c))
ppm('lean_u_turned', (0, -s, c))
# the plane's corners, front face +y (counter-clockwise seen from above)
P = [(-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)]
def model(name, uv, image, tangent=None, turn=None):
    # uv(x, z) -> (u, v) with v up, written as glTF's v, which runs down
    pos = [a for p in P for a in p]
    tex = [a for p in P for a in (uv(p[0], p[2])[0], 1 - uv(p[0], p[2])[1])]
    nrm = [0, 1, 0] * 4
    idx = [0, 1, 2, 0, 2, 3]
    parts = [struct.pack('<12f', *pos), struct.pack('<12f', *nrm), struct.pack('<8f', *tex)]
    attrs = {'POSITION': 0, 'NORMAL': 1, 'TEXCOORD_0': 2}
    if tangent:
        parts.append(struct.pack('<16f', *(list(tangent) * 4)))
        attrs['TANGENT'] = 3
    views, accs, at = [], [], 0
    types = ['VEC3', 'VEC3', 'VEC2', 'VEC4']
    for k, p in enumerate(parts):
        views.append({'buffer': 0, 'byteOffset': at, 'byteLength': len(p)})
        acc = {'bufferView': k, 'componentType': 5126, 'count': 4, 'type': types[k]}
        if k == 0:
            acc['min'], acc['max'] = [-1, 0, -1], [1, 0, 1]
        accs.append(acc)
        at += len(p)
    ib = struct.pack('<6H', *idx)
    views.append({'buffer': 0, 'byteOffset': at, 'byteLength': len(ib)})
    accs.append({'bufferView': len(views) - 1, 'componentType': 5123, 'count': 6, 'type': 'SCALAR'})
    data = b''.join(parts) + ib
    info = {'index': 0}
    used = []
    if turn is not None:
        info['extensions'] = {'KHR_texture_transform': {'rotation': turn}}
        used = ['KHR_texture_transform']
    g = {'asset': {'version': '2.0'}, 'scene': 0, 'scenes': [{'nodes': [0]}],
         'nodes': [{'mesh': 0}],
         'buffers': [{'byteLength': len(data), 'uri': 'data:application/octet-stream;base64,' +
                      base64.b64encode(data).decode()}],
         'bufferViews': views, 'accessors': accs,
         'meshes': [{'primitives': [{'attributes': attrs, 'indices': len(accs) - 1,
                                     'material': 0}]}],
         'materials': [{'name': 'leaning', 'normalTexture': info,
                        'pbrMetallicRoughness': {'baseColorFactor': [0.5, 0.5, 0.5, 1],
                                                 'metallicFactor': 0}}],
         'textures': [{'source': 0}], 'images': [{'uri': image + '.ppm'}]}
    if used:
        g['extensionsUsed'] = used
    json.dump(g, open('%s/%s.gltf' % (out, name), 'w'))
model('file', lambda x, z: ((x + 1) / 2, (z + 1) / 2), 'lean_tb', tangent=(0, 0, 1, -1))
model('made', lambda x, z: ((z + 1) / 2, (1 - x) / 2), 'lean_tb')
model('ignored', lambda x, z: ((x + 1) / 2, (z + 1) / 2), 'lean_tb')
model('turned', lambda x, z: ((x + 1) / 2, (1 - z) / 2), 'lean_u', turn=math.pi / 2)
model('preturned', lambda x, z: ((x + 1) / 2, (1 - z) / 2), 'lean_u_turned')
# lights from (z - x) / sqrt 2 and from +z, 40 degrees off the vertical
k = math.sin(math.radians(40)) / math.sqrt(2)
for name, d in (('diag', (k, -math.cos(math.radians(40)), -k)),
                ('plusz', (0, -math.cos(math.radians(40)), -math.sin(math.radians(40))))):
    open('%s/light_%s' % (out, name), 'w').write('light distant %.9g %.9g %.9g white 1\n' % d)
PYEOF
mean() {  # mean EXR: the mean over pixels of the mean of R, G, B
  oiiotool "$1" --printstats 2>&1 | sed -n 's/.*Stats Avg: *//p' | head -1 |
    awk '{ print ($1 + $2 + $3) / 3 }'
}
declare -A M
for b in cpu opencl; do
  for m in file made ignored turned preturned; do
    light=light_diag; case $m in turned | preturned) light=light_plusz ;; esac
    printf 'image 32 32\ncamera position 0 5 0 direction 0 -1 0 up 0 0 -1 orthographic 1.5\nspectrum white equal\n%s\nmesh %s.gltf\n' \
      "$(cat "$T/$light")" $m > "$T/$m.scene"
    "$BIN" render "$T/$m.scene" --backend $b --mode rgb --spp 16 --seed 5 -o "$T/$m-$b.exr" \
      > /dev/null 2>"$T/$m-$b.err" || bad "$b: render of $m: $(cat "$T/$m-$b.err")"
    M[$m-$b]=$(mean "$T/$m-$b.exr")
  done
  echo "$b: file ${M[file-$b]} made ${M[made-$b]} ignored ${M[ignored-$b]}" \
    "turned ${M[turned-$b]} preturned ${M[preturned-$b]}"
  rel() { awk -v a="$1" -v b="$2" 'BEGIN { d = (a - b) / b; print d < 0 ? -d : d }'; }
  r=$(rel "${M[file-$b]}" "${M[made-$b]}")
  check "$b: the file's TANGENT frame gives its made peer's image (off $r <= $TOL)" num "$r" '<=' $TOL
  r=$(rel "${M[ignored-$b]}" "${M[made-$b]}")
  check "$b: the made frame instead leans elsewhere (off $r >= 0.1)" num "$r" '>=' 0.1
  r=$(rel "${M[turned-$b]}" "${M[preturned-$b]}")
  check "$b: a turned map's frame turns with it (off $r <= $TOL)" num "$r" '<=' $TOL
  check "$b: no warning about tangents or transforms" \
    bash -c "! grep -qiE 'tangent|transform' '$T/file-$b.err' '$T/turned-$b.err'"
done
finish
