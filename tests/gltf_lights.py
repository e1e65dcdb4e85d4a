#!/usr/bin/env python3
"""glTF KHR_lights_punctual for tests/cli_gltf_lights.sh.

gltf_lights.py gen ROOT DIR: writes DIR/{point,spot,directional}.gltf, each a
10 x 10 floor quad at y = 0 and one light placed by a node under a parent
(their transforms composed), and the bad files DIR/bad_*.gltf.
  point        10 cd, color (1, 0.8, 0.6), at (0, 2, 0) (parent y + 1, own y + 1)
  spot         10 cd, inner 20, outer 30 degrees, at (0, 2, 0), its -z turned
               to -y by a quaternion (-90 degrees about x)
  directional  3 lux travelling along (1, -2, 0) / sqrt 5 (a node `matrix`)

gltf_lights.py check KIND EXR [SCALE]: the image of a camera at (0, 6 SCALE,
0) looking down (fov 60, 64 x 64) against the closed form on a Lambertian
floor of rho = 0.5, L = rho I f cos(theta) / (pi d^2) (f glTF's spot falloff:
t^2, t = (cos - cos outer) / (cos inner - cos outer) clamped to [0, 1]) or rho
E cos(theta) / pi, averaged over each pixel (8 x 8 points) and over rings 2
pixels wide about the centre; prints each ring's ratio and the worst ring's
deviation as a fraction of the peak.
"""
import math
import os
import re
import subprocess
import sys

RHO, D, W, SUB = 0.5, 2.0, 64, 8
COLOUR = (1.0, 0.8, 0.6)
INNER, OUTER = 20.0, 30.0


def luminance(c):
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]


def gen(root, out):
    sys.path.insert(0, os.path.join(root, 'tools'))
    import gen_meshes as g
    quad = [(-5, 0, -5), (5, 0, -5), (5, 0, 5), (-5, 0, 5)]
    mats = [{'name': 'floor', 'pbrMetallicRoughness': {'baseColorFactor': [0.5, 0.5, 0.5, 1],
                                                       'metallicFactor': 0.0}}]

    def write(name, lights, node, index=0):
        doc, buf = g.gltf_doc(quad, [([0, 2, 1, 0, 3, 2], 0)], [{'mesh': 0}], [0, 1], mats)
        doc['extensionsUsed'] = ['KHR_lights_punctual']
        doc['extensions'] = {'KHR_lights_punctual': {'lights': lights}}
        node = dict(node, name='lamp', extensions={'KHR_lights_punctual': {'light': index}})
        doc['nodes'] += [{'name': 'rig', 'translation': [0, 1, 0], 'children': [2]}, node]
        g.write_gltf(os.path.join(out, name + '.gltf'), doc, buf)

    s = math.sqrt(0.5)
    z = [-1 / math.sqrt(5), 2 / math.sqrt(5), 0]  # the node's +z: against the travel
    x = [0, 0, 1]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    up = {'translation': [0, 1, 0]}
    down = {'translation': [0, 1, 0], 'rotation': [-s, 0, 0, s]}
    spot = {'type': 'spot', 'intensity': 10, 'spot': {'innerConeAngle': math.radians(INNER),
                                                      'outerConeAngle': math.radians(OUTER)}}
    write('point', [{'type': 'point', 'color': list(COLOUR), 'intensity': 10}], up)
    write('spot', [spot], down)
    write('directional', [{'type': 'directional', 'intensity': 3}],
          {'matrix': x + [0] + y + [0] + z + [0] + [0, 0, 0, 1]})
    write('bad_index', [spot], down, index=3)
    write('bad_type', [{'type': 'area'}], up)
    write('bad_cone', [dict(spot, spot={'innerConeAngle': 0.6, 'outerConeAngle': 0.5})], down)
    write('bad_colour', [{'type': 'point', 'color': [1, -1, 1]}], up)
    write('range', [{'type': 'point', 'range': 4}], up)


def closed_form(kind, x, z, scale):
    if kind == 'directional':
        return RHO * 3 * (2 / math.sqrt(5)) / math.pi
    d2 = D * D + x * x + z * z
    ct = D / math.sqrt(d2)
    f = 1.0
    if kind == 'spot':
        co, ci = math.cos(math.radians(OUTER)), math.cos(math.radians(INNER))
        t = min(1.0, max(0.0, (ct - co) / (ci - co)))
        f = t * t
    i = 10 * (luminance(COLOUR) if kind == 'point' else 1.0)
    return RHO * i * f * ct / (math.pi * d2)


def check(kind, exr, scale):
    ys = {}
    dump = subprocess.run(['oiiotool', '--dumpdata', exr], capture_output=True, text=True).stdout
    for line in dump.splitlines():
        m = re.match(r'\s*Pixel \((\d+), (\d+)\): (\S+) (\S+) (\S+)', line)
        if m:
            ys[int(m.group(1)), int(m.group(2))] = luminance([float(v) for v in m.group(3, 4, 5)])
    if len(ys) != W * W:
        sys.exit('%s: %d pixels read' % (exr, len(ys)))
    px = 6 * math.tan(math.radians(30)) / (W / 2)  # a pixel's width on the floor (scale 1)
    rings = {}
    for (i, j), y in ys.items():
        want = sum(closed_form(kind, (i + (u + .5) / SUB - W / 2) * px,
                               (j + (v + .5) / SUB - W / 2) * px, scale)
                   for u in range(SUB) for v in range(SUB)) / SUB ** 2
        a = rings.setdefault(int(math.hypot(i + .5 - W / 2, j + .5 - W / 2) / 2), [0.0, 0.0, 0])
        a[0] += y
        a[1] += want
        a[2] += 1
    peak = max(a[1] / a[2] for a in rings.values())
    worst = max(abs(a[0] - a[1]) / a[2] / peak for a in rings.values())
    print(kind, 'rings', ' '.join('%d:%.4f' % (r, a[0] / a[1] if a[1] else a[0])
                                 for r, a in sorted(rings.items())), file=sys.stderr)
    print('%.6f' % worst)


if __name__ == '__main__':
    if len(sys.argv) == 4 and sys.argv[1] == 'gen':
        gen(sys.argv[2], sys.argv[3])
    elif len(sys.argv) in (4, 5) and sys.argv[1] == 'check':
        check(sys.argv[2], sys.argv[3], float(sys.argv[4]) if len(sys.argv) == 5 else 1.0)
    else:
        sys.exit(__doc__)
