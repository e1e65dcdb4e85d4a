#!/usr/bin/env python3
"""Writes small test meshes, the same cube in every format the `mesh`
statement reads, plus the expected triangles as text:

  cube.obj + cube.mtl   OBJ with two materials, 'red' (+x, -x faces) and 'white'
  cube_ascii.ply        ASCII PLY, face lists
  cube_binary.ply       binary little-endian PLY, face lists
  cube_strips.ply       ASCII PLY, triangle strips (one per face, -1 between)
  cube_strips_be.ply    binary big-endian PLY, the same strips in one list int int,
                        vertices with colours and the +-x faces as a face element
  grid_faces.ply        binary PLY, a bumpy 16x9-quad height field as triangle faces
  grid_strips.ply       ASCII PLY, the same triangles as strips, one per row: rows
                        restart at -1 or are joined by repeated indices (whose
                        triangles are no triangles)
  tex.png               a 3x2 RGB texture; tex.mean its mean linear colour (each
                        sRGB code decoded, then averaged)
  tex_cube.obj/.mtl     the cube, 'red' with map_Kd tex.png (Kd the factor)
  tex_cube.gltf / .glb  the cube, 'red' with baseColorTexture tex.png (the .glb's
                        embedded in its binary chunk)
  cube.gltf / cube.glb  glTF 2.0, one mesh of two primitives (the two materials)
  cube_ascii.stl / cube_binary.stl
  cube.tris             the 12 triangles, 9 numbers a line, front faces outward
  hier.gltf + hier.tris glTF node hierarchy: the cube used by three nodes
                        (a translation; a rotation and translation under a scaled
                        parent; a mirror)
  quad_emit.gltf        one emissive quad facing -z (towards a camera on -z)
  sphere_n.obj/.ply/.gltf, sphere_n_strips.ply
                        a unit sphere (8 rings of 16 segments, 224 triangles) with
                        vertex normals (vn; nx ny nz; NORMAL), each its vertex's
                        position; the glTF's node scales it by (1, 2, 1), so its
                        normals must come out as (x, y / 4, z) of its positions
  metal.gltf            a quad per material: 'gold' metallic 1, base colour (1, 0.78,
                        0.34), roughness 0; 'steel' metallic 1, roughness 0.5; 'half'
                        metallic 0.3; 'glass' transmission 1 and ior 1.5
  metal.obj + .mtl      'copper' Kd 0, Ks (0.95 0.64 0.54), Ns 200; 'paint' Kd (0.5 0.1
                        0.1), Ks 0.04, Ns 50
  pbr.gltf              a quad per material (docs/SCENE_FORMAT.md's mesh-material rows):
                        'solid' transmission 1, ior 1.33, roughness 0.3, a volume
                        (thickness 0.5, attenuation colour (0.9 0.5 0.2) at distance 2);
                        'thin' transmission 1, roughness 0, no volume; 'part'
                        transmission 0.7, roughness 0.1; 'low' transmission 0.3, base (0.3 0.6 0.3);
                        'plastic' base (0.2 0.4 0.8), roughness 0.6, ior 1.7
  pbr.obj + .mtl        'paint' Kd (0.5 0.1 0.1), Ks 0.04, Ns 50, Ni 1.6; 'glass' Kd 0,
                        Ks 1, Ns 1000, Ni 1.45, illum 7; 'veil' Kd 0.5, d 0.5
  pbr_spheres.gltf      two unit spheres at x = -1.2 and 1.2 (224 triangles each):
                        'amber' transmission 1, ior 1.5, roughness 0, a volume
                        (attenuation colour (0.9 0.6 0.2) at distance 1); 'paint'
                        base (0.7 0.15 0.1), roughness 0.3
  tilt.obj              a 20 x 20 quad at z = 0 facing +z whose vertex normals all
                        lean 60 degrees towards +x (a shading normal far from the
                        geometric one)
  smooth_box.scene      the conductor test box with a smooth conductor sphere and a
                        smooth diffuse sphere (sphere_n.obj, sphere_n.ply)
  leak_KIND.scene, leak_lit_KIND.scene
                        tilt.obj (KIND: diffuse with `smooth`, a rough or a smooth
                        conductor, a smooth or a rough coating) seen from the front, a white wall behind it
                        (leak: lit by a light behind the quad: nothing may reach the
                        camera; leak_lit: the light in front of the quad instead)
  smooth_glass_box.scene
                        the conductor test box with smooth spheres (sphere_n.obj) of
                        clear glass, rough glass (alpha 0.3), a smooth and a rough
                        (alpha 0.2) coating
  sphere_fine.ply       a unit sphere of 48 rings of 96 segments (9024 triangles)
                        with vertex normals (each its vertex's position)
  invisible.scene       sphere_fine.ply as smooth clear glass (index 1.5) in a
                        uniform background, no emitter: the image is the background
                        (invisible_coarse.scene: the same with sphere_n.ply)
  big.ply + (N given)   a procedural binary PLY of about N triangles (a bumpy sphere)
  big.scene             with N: the Cornell box (scenes/cornell.scene) with big.ply in it
  big_text.scene        the same box and sphere, the sphere as `tri` statements
                        (its degenerate pole triangles left out)

Coordinates are small integers, exact in every format, so all must import to
the same triangles bit for bit.

With --scale, one procedural mesh of about N triangles for the scale benchmark
(bench/scale.sh), as binary PLY, and a scene beside it that frames it (the
mesh fills the view: every camera ray hits it) under an emissive quad:
  sphere   a bumpy sphere seen from inside (closed: paths bounce until absorbed)
  torus    a bumpy torus seen from inside its tube
  soup     N random triangles in a cube, edges about 4/cbrt(N) of its side,
           seen from the cube's front face (seeded: the same N gives the same soup)
With --metals, the conductor scenes (their objects as `tri` statements, so each
scene is one self-contained file):
  metals.scene          the Cornell box of scenes/cornell.scene with smooth gold,
                        copper and aluminium blocks and rough (GGX) spheres of them
  copper_sodium.scene   copper under a low-pressure sodium lamp (the failure scene)

With --materials, scenes/materials.scene and the mesh it places five times,
materials_sphere.ply (a unit sphere of 12 rings of 24 segments, 528 triangles,
ASCII PLY with its vertex normals, each its vertex's position).

With --coated, the coated scenes (likewise `tri` statements):
  coated.scene          the Cornell box with smooth and rough (GGX) coated objects:
                        red plastic, glossy blue and yellow paint, a white glaze
  coated_spiky.scene    saturated coated paints under the F11 tri-band lamp (the
                        failure scene: rgb)

usage: gen_meshes.py OUTDIR [BIG_TRIANGLES]
       gen_meshes.py --scale SHAPE N OUT.ply OUT.scene   (prints the triangle count)
       gen_meshes.py --metals OUTDIR
       gen_meshes.py --coated OUTDIR
       gen_meshes.py --glass OUTDIR   (glass.scene, glass_deep.scene)
       gen_meshes.py --materials OUTDIR   (materials.scene, materials_sphere.ply)
       gen_meshes.py --dispersion OUTDIR   (prism.scene, sf11_sphere.scene, prism_wall.scene)"""
import base64, json, math, os, struct, sys

# cube [0,2]^3, faces as quads (a b c d) counter-clockwise seen from outside
V = [(x, y, z) for x in (0, 2) for y in (0, 2) for z in (0, 2)]  # index = 4x + 2y + z
QUADS = [((4, 6, 7, 5), 'red'),    # +x
         ((0, 1, 3, 2), 'red'),    # -x
         ((2, 3, 7, 6), 'white'),  # +y
         ((0, 4, 5, 1), 'white'),  # -y
         ((1, 5, 7, 3), 'white'),  # +z
         ((0, 2, 6, 4), 'white')]  # -z
TRIS = []  # (i, j, k, material)
for (a, b, c, d), m in QUADS:
    TRIS += [(a, b, c, m), (a, c, d, m)]
MATS = {'red': (0.8, 0.1, 0.1), 'white': (0.7, 0.7, 0.7)}


def w(path, data, mode='w'):
    with open(path, mode) as f:
        f.write(data)


def fmt(v):
    return ' '.join('%g' % c for c in v)


def write_tris(path, tris):
    w(path, ''.join(' '.join(fmt(p) for p in t) + '\n' for t in tris))


def obj(out):
    w(os.path.join(out, 'cube.mtl'), ''.join(
        'newmtl %s\nKd %s\n\n' % (m, fmt(c)) for m, c in MATS.items()))
    s = 'mtllib cube.mtl\n' + ''.join('v %s\n' % fmt(p) for p in V)
    for m in MATS:
        s += 'usemtl %s\n' % m + ''.join('f %d %d %d\n' % (i + 1, j + 1, k + 1)
                                         for i, j, k, mm in TRIS if mm == m)
    w(os.path.join(out, 'cube.obj'), s)


def ply_header(fmt_name, nv, elem, nf, listtype='int'):
    return ('ply\nformat %s 1.0\ncomment generated by tools/gen_meshes.py\n'
            'element vertex %d\nproperty float x\nproperty float y\nproperty float z\n'
            'element %s %d\nproperty list uchar %s vertex_indices\nend_header\n'
            % (fmt_name, nv, elem, nf, listtype))


def ply(out):
    s = ply_header('ascii', len(V), 'face', len(TRIS))
    s += ''.join(fmt(p) + '\n' for p in V) + ''.join('3 %d %d %d\n' % t[:3] for t in TRIS)
    w(os.path.join(out, 'cube_ascii.ply'), s)
    b = ply_header('binary_little_endian', len(V), 'face', len(TRIS)).encode()
    b += b''.join(struct.pack('<3f', *p) for p in V)
    b += b''.join(struct.pack('<B3i', 3, *t[:3]) for t in TRIS)
    w(os.path.join(out, 'cube_binary.ply'), b, 'wb')
    # strips b c a d: triangles (b c a) = (a b c) and, odd so reversed, (a c d)
    idx = []
    for (a, b_, c, d), _ in QUADS:
        idx += ([-1] if idx else []) + [b_, c, a, d]
    s = ply_header('ascii', len(V), 'tristrips', 1).replace('vertex_indices', 'vertex_indices')
    s += ''.join(fmt(p) + '\n' for p in V) + '%d %s\n' % (len(idx), ' '.join(map(str, idx)))
    w(os.path.join(out, 'cube_strips.ply'), s)
    # big-endian: x y z and a colour per vertex; the x faces as faces, the
    # other four faces as strips restarting at -1 (one list for them all)
    idx = []
    faces = []
    for (a, b_, c, d), m in QUADS:
        if m == 'red':
            faces.append((a, b_, c, d))
        else:
            idx += ([-1] if idx else []) + [b_, c, a, d]
    hdr = ('ply\nformat binary_big_endian 1.0\nelement vertex %d\nproperty float x\n'
           'property float y\nproperty float z\nproperty uchar red\nproperty uchar green\n'
           'property uchar blue\nelement face %d\nproperty list uchar int vertex_indices\n'
           'element tristrips 1\nproperty list int int vertex_indices\nend_header\n'
           % (len(V), len(faces)))
    b = hdr.encode() + b''.join(struct.pack('>3f3B', *p, 9, 8, 7) for p in V)
    b += b''.join(struct.pack('>B4i', 4, *f) for f in faces)
    b += struct.pack('>i', len(idx)) + b''.join(struct.pack('>i', i) for i in idx)
    w(os.path.join(out, 'cube_strips_be.ply'), b, 'wb')


def strip_tris(idx):
    """The triangles of a strip list (the PLY convention, as a check)."""
    tris, run = [], []
    for i in idx:
        if i < 0:
            run = []
            continue
        run.append(i)
        if len(run) >= 3:
            a, b, c = run[-3:]
            t = (b, a, c) if (len(run) - 3) % 2 else (a, b, c)
            if len(set(t)) == 3:
                tris.append(t)
    return tris


def grid(out):
    nx, ny = 16, 9
    f32 = lambda v: struct.unpack('<f', struct.pack('<f', v))[0]  # %.9g then reads back exactly
    verts = [(x * 0.5, y * 0.5, f32(0.25 * math.sin(x * 0.9) * math.cos(y * 1.3)))
             for y in range(ny + 1) for x in range(nx + 1)]
    vid = lambda x, y: y * (nx + 1) + x
    faces, idx = [], []
    for y in range(ny):
        # quad (t_j, b_j, b_j+1, t_j+1) counter-clockwise from +z, t the row above
        for x in range(nx):
            t0, b0, t1, b1 = vid(x, y + 1), vid(x, y), vid(x + 1, y + 1), vid(x + 1, y)
            faces += [(t0, b0, t1), (t1, b0, b1)]
        row = [v for x in range(nx + 1) for v in (vid(x, y + 1), vid(x, y))]
        if not idx:
            idx = row
        elif y % 2:  # joined: last and first repeated (an even count keeps the parity)
            idx += [idx[-1], row[0]] + row
        else:
            idx += [-1] + row
    assert sorted(strip_tris(idx)) == sorted(faces)
    write_ply(os.path.join(out, 'grid_faces.ply'), [c for p in verts for c in p], faces)
    s = ply_header('ascii', len(verts), 'tristrips', 1, 'int').replace('uchar int', 'int int')
    s += ''.join('%.9g %.9g %.9g\n' % p for p in verts) + '%d %s\n' % (len(idx), ' '.join(map(str, idx)))
    w(os.path.join(out, 'grid_strips.ply'), s)


def srgb_decode(c):
    c /= 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


TEX = [[(255, 128, 0), (200, 30, 90), (0, 0, 0)],
       [(255, 255, 64), (10, 250, 20), (90, 90, 255)]]  # 3x2, rows top to bottom
TEX_FACTOR = (0.9, 0.6, 0.3)  # the textured 'red''s colour factor (Kd, baseColorFactor)


def png(rows):
    import zlib
    raw = b''.join(b'\0' + bytes(c for px in r for c in px) for r in rows)
    def chunk(t, d):
        return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d))
    return (b'\x89PNG\r\n\x1a\n' +
            chunk(b'IHDR', struct.pack('>IIBBBBB', len(rows[0]), len(rows), 8, 2, 0, 0, 0)) +
            chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))


def textured(out):
    pix = [px for r in TEX for px in r]
    mean = [sum(srgb_decode(px[k]) for px in pix) / len(pix) for k in range(3)]
    w(os.path.join(out, 'tex.mean'), '%.9g %.9g %.9g\n' % tuple(mean))
    image = png(TEX)
    w(os.path.join(out, 'tex.png'), image, 'wb')
    mats = dict(MATS, red=TEX_FACTOR)
    w(os.path.join(out, 'tex_cube.mtl'), ''.join(
        'newmtl %s\nKd %s\n%s\n' % (m, fmt(c), 'map_Kd tex.png\n' if m == 'red' else '')
        for m, c in mats.items()))
    s = 'mtllib tex_cube.mtl\n' + ''.join('v %s\n' % fmt(p) for p in V)
    for m in MATS:
        s += 'usemtl %s\n' % m + ''.join('f %d %d %d\n' % (i + 1, j + 1, k + 1)
                                         for i, j, k, mm in TRIS if mm == m)
    w(os.path.join(out, 'tex_cube.obj'), s)
    names = list(MATS)
    prims = [([i for t in TRIS if t[3] == m for i in t[:3]], names.index(m)) for m in names]
    materials = gltf_materials(names)
    red = materials[names.index('red')]['pbrMetallicRoughness']
    red['baseColorFactor'] = list(TEX_FACTOR) + [1.0]
    red['baseColorTexture'] = {'index': 0}
    doc, buf = gltf_doc(V, prims, [{'mesh': 0}], [0], materials)
    doc['textures'] = [{'source': 0}]
    doc['images'] = [{'uri': 'tex.png'}]
    write_gltf(os.path.join(out, 'tex_cube.gltf'), doc, buf)
    buf = buf + b'\0' * (-len(buf) % 4)
    doc['bufferViews'].append({'buffer': 0, 'byteOffset': len(buf), 'byteLength': len(image)})
    doc['images'] = [{'bufferView': len(doc['bufferViews']) - 1, 'mimeType': 'image/png'}]
    buf += image
    doc['buffers'][0]['byteLength'] = len(buf)
    write_glb(os.path.join(out, 'tex_cube.glb'), doc, buf)


def stl(out):
    def normal(t):
        p, q, r = (V[i] for i in t[:3])
        e1 = [q[k] - p[k] for k in range(3)]
        e2 = [r[k] - p[k] for k in range(3)]
        n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
             e1[0] * e2[1] - e1[1] * e2[0])
        l = math.sqrt(sum(c * c for c in n))
        return tuple(c / l for c in n)
    s = 'solid cube\n'
    for t in TRIS:
        s += ' facet normal %s\n  outer loop\n' % fmt(normal(t))
        s += ''.join('   vertex %s\n' % fmt(V[i]) for i in t[:3]) + '  endloop\n endfacet\n'
    w(os.path.join(out, 'cube_ascii.stl'), s + 'endsolid cube\n')
    b = b'generated by tools/gen_meshes.py'.ljust(80, b' ') + struct.pack('<I', len(TRIS))
    for t in TRIS:
        b += struct.pack('<3f', *normal(t)) + b''.join(struct.pack('<3f', *V[i]) for i in t[:3])
        b += struct.pack('<H', 0)
    w(os.path.join(out, 'cube_binary.stl'), b, 'wb')


def gltf_doc(positions, prims, nodes, scene_nodes, materials):
    """positions: list of xyz; prims: list of (index list, material index or None)."""
    pos = b''.join(struct.pack('<3f', *p) for p in positions)
    buf = bytearray(pos)
    accessors = [{'bufferView': 0, 'componentType': 5126, 'count': len(positions), 'type': 'VEC3',
                  'min': [min(p[k] for p in positions) for k in range(3)],
                  'max': [max(p[k] for p in positions) for k in range(3)]}]
    views = [{'buffer': 0, 'byteOffset': 0, 'byteLength': len(pos)}]
    primitives = []
    for idx, mat in prims:
        data = b''.join(struct.pack('<I', i) for i in idx)
        views.append({'buffer': 0, 'byteOffset': len(buf), 'byteLength': len(data)})
        accessors.append({'bufferView': len(views) - 1, 'componentType': 5125,
                          'count': len(idx), 'type': 'SCALAR'})
        buf += data
        p = {'attributes': {'POSITION': 0}, 'indices': len(accessors) - 1, 'mode': 4}
        if mat is not None:
            p['material'] = mat
        primitives.append(p)
    doc = {'asset': {'version': '2.0', 'generator': 'tools/gen_meshes.py'},
           'scene': 0, 'scenes': [{'nodes': scene_nodes}], 'nodes': nodes,
           'meshes': [{'primitives': primitives}], 'materials': materials,
           'accessors': accessors, 'bufferViews': views,
           'buffers': [{'byteLength': len(buf)}]}
    return doc, bytes(buf)


def write_gltf(path, doc, buf):
    doc = json.loads(json.dumps(doc))
    doc['buffers'][0]['uri'] = ('data:application/octet-stream;base64,' +
                                base64.b64encode(buf).decode())
    w(path, json.dumps(doc, indent=1))


def write_glb(path, doc, buf):
    js = json.dumps(doc).encode()
    js += b' ' * (-len(js) % 4)
    buf = buf + b'\0' * (-len(buf) % 4)
    body = struct.pack('<I4s', len(js), b'JSON') + js + struct.pack('<I4s', len(buf), b'BIN\0') + buf
    w(path, struct.pack('<4sII', b'glTF', 2, 12 + len(body)) + body, 'wb')


def gltf_materials(names):
    return [{'name': m, 'pbrMetallicRoughness': {'baseColorFactor': list(MATS[m]) + [1.0],
                                                 'metallicFactor': 0.0}} for m in names]


def gltf(out):
    names = list(MATS)
    prims = [([i for t in TRIS if t[3] == m for i in t[:3]], names.index(m)) for m in names]
    doc, buf = gltf_doc(V, prims, [{'mesh': 0}], [0], gltf_materials(names))
    write_gltf(os.path.join(out, 'cube.gltf'), doc, buf)
    write_glb(os.path.join(out, 'cube.glb'), doc, buf)
    # hierarchy: node 0 translated; node 1 (scale 2 1 1) with child 2 rotated 90 deg
    # about z and moved; node 3 mirrored in x (its faces' winding reversed to keep them outward)
    c, s = 0.0, 1.0  # the quaternion of 90 degrees about z is (0, 0, sin 45, cos 45)
    q = math.sqrt(0.5)
    nodes = [{'mesh': 0, 'translation': [10, 0, 0]},
             {'scale': [2, 1, 1], 'children': [2]},
             {'mesh': 0, 'rotation': [0, 0, q, q], 'translation': [0, 0, 5]},
             {'mesh': 0, 'scale': [-1, 1, 1], 'translation': [-10, 0, 0]}]
    doc, buf = gltf_doc(V, prims, nodes, [0, 1, 3], gltf_materials(names))
    write_gltf(os.path.join(out, 'hier.gltf'), doc, buf)
    tris = []
    for t in TRIS:
        p = [V[i] for i in t[:3]]
        tris.append([(x + 10, y, z) for x, y, z in p])
        tris.append([(2 * (c * x - s * y), s * x + c * y, z + 5) for x, y, z in p])
        m = [(-x - 10, y, z) for x, y, z in p]
        tris.append([m[0], m[2], m[1]])
    write_tris(os.path.join(out, 'hier.tris'), tris)
    # an emissive quad at z = 0, x and y in [-1, 1], front face towards -z
    quad = [(-1, -1, 0), (-1, 1, 0), (1, 1, 0), (1, -1, 0)]
    mat = [{'name': 'glow', 'emissiveFactor': [1.0, 1.0, 1.0],
            'pbrMetallicRoughness': {'baseColorFactor': [0, 0, 0, 1], 'metallicFactor': 0.0}}]
    doc, buf = gltf_doc(quad, [([0, 1, 2, 0, 2, 3], 0)], [{'mesh': 0}], [0], mat)
    write_gltf(os.path.join(out, 'quad_emit.gltf'), doc, buf)


def sphere_n(rings=8, segs=16):
    """A unit sphere: vertices (poles single), triangles counter-clockwise
    seen from outside; a vertex's normal is its position."""
    verts = [(0.0, 1.0, 0.0)]
    for i in range(1, rings):
        th = math.pi * i / rings
        for j in range(segs):
            ph = 2 * math.pi * j / segs
            verts.append((math.sin(th) * math.cos(ph), math.cos(th), -math.sin(th) * math.sin(ph)))
    verts.append((0.0, -1.0, 0.0))
    def ring(i, j):
        return 1 + (i - 1) * segs + j % segs
    tris = []
    for j in range(segs):
        tris.append((0, ring(1, j), ring(1, j + 1)))
        for i in range(1, rings - 1):
            a, b, c, d = ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)
            tris += [(a, b, c), (a, c, d)]
        tris.append((ring(rings - 1, j), len(verts) - 1, ring(rings - 1, j + 1)))
    return verts, tris


def write_sphere_ply(path, rings, segs):
    """sphere_n(rings, segs) as ASCII PLY with its vertex normals."""
    verts, tris = sphere_n(rings, segs)
    w(path, 'ply\nformat ascii 1.0\ncomment generated by tools/gen_meshes.py\n'
      'element vertex %d\nproperty float x\nproperty float y\nproperty float z\n'
      'property float nx\nproperty float ny\nproperty float nz\n'
      'element face %d\nproperty list uchar int vertex_indices\nend_header\n'
      % (len(verts), len(tris)) + ''.join('%.7f %.7f %.7f %.7f %.7f %.7f\n' % (v + v)
                                          for v in verts) +
      ''.join('3 %d %d %d\n' % t for t in tris))


def metal_meshes(out):
    quads = []
    for i in range(4):
        quads += [(2 * i, 0, 0), (2 * i + 1, 0, 0), (2 * i + 1, 1, 0), (2 * i, 1, 0)]
    mats = [{'name': 'gold', 'pbrMetallicRoughness': {'baseColorFactor': [1.0, 0.78, 0.34, 1.0],
                                                      'metallicFactor': 1.0, 'roughnessFactor': 0.0}},
            {'name': 'steel', 'pbrMetallicRoughness': {'baseColorFactor': [0.56, 0.57, 0.58, 1.0],
                                                       'metallicFactor': 1.0, 'roughnessFactor': 0.5}},
            {'name': 'half', 'pbrMetallicRoughness': {'baseColorFactor': [0.5, 0.5, 0.5, 1.0],
                                                      'metallicFactor': 0.3}},
            {'name': 'glass', 'pbrMetallicRoughness': {'baseColorFactor': [1, 1, 1, 1.0],
                                                       'metallicFactor': 0.0, 'roughnessFactor': 0.0},
             'extensions': {'KHR_materials_transmission': {'transmissionFactor': 1.0},
                            'KHR_materials_ior': {'ior': 1.5}}}]
    prims = [([4 * i, 4 * i + 1, 4 * i + 2, 4 * i, 4 * i + 2, 4 * i + 3], i) for i in range(4)]
    doc, buf = gltf_doc(quads, prims, [{'mesh': 0}], [0], mats)
    doc['extensionsUsed'] = ['KHR_materials_transmission', 'KHR_materials_ior']
    write_gltf(os.path.join(out, 'metal.gltf'), doc, buf)
    w(os.path.join(out, 'metal.mtl'), 'newmtl copper\nKd 0 0 0\nKs 0.95 0.64 0.54\nNs 200\n'
      'illum 3\n\nnewmtl paint\nKd 0.5 0.1 0.1\nKs 0.04 0.04 0.04\nNs 50\nillum 2\n')
    w(os.path.join(out, 'metal.obj'), 'mtllib metal.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n'
      'v 2 0 0\nv 3 0 0\nv 3 1 0\nv 2 1 0\nusemtl copper\nf 1 2 3 4\nusemtl paint\nf 5 6 7 8\n')


def smooth_meshes(out):
    verts, tris = sphere_n()
    mtl = 'newmtl shiny\nKd 0.5 0.5 0.5\n'
    w(os.path.join(out, 'sphere_n.mtl'), mtl)
    s = 'mtllib sphere_n.mtl\n' + ''.join('v %r %r %r\n' % v for v in verts)
    s += ''.join('vn %r %r %r\n' % v for v in verts) + 'usemtl shiny\n'
    s += ''.join('f %d//%d %d//%d %d//%d\n' % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1)
                 for a, b, c in tris)
    w(os.path.join(out, 'sphere_n.obj'), s)
    hdr = ('ply\nformat ascii 1.0\ncomment generated by tools/gen_meshes.py\n'
           'element vertex %d\nproperty float x\nproperty float y\nproperty float z\n'
           'property float nx\nproperty float ny\nproperty float nz\n' % len(verts))
    vs = ''.join('%r %r %r %r %r %r\n' % (v + v) for v in verts)
    w(os.path.join(out, 'sphere_n.ply'), hdr + 'element face %d\n'
      'property list uchar int vertex_indices\nend_header\n' % len(tris) + vs +
      ''.join('3 %d %d %d\n' % t for t in tris))
    # the same triangles as one-triangle strips (specmip's own PLY reader)
    w(os.path.join(out, 'sphere_n_strips.ply'), hdr + 'element tristrips 1\n'
      'property list int int vertex_indices\nend_header\n' + vs +
      '%d %s\n' % (4 * len(tris) - 1, ' -1 '.join('%d %d %d' % t for t in tris)))
    # glTF: positions and normals, under a node scaled by (1, 2, 1)
    doc, buf = gltf_doc(verts, [([i for t in tris for i in t], 0)], [{'mesh': 0, 'scale': [1, 2, 1]}],
                        [0], [{'name': 'shiny', 'pbrMetallicRoughness': {
                            'baseColorFactor': [0.5, 0.5, 0.5, 1.0], 'metallicFactor': 0.0}}])
    nrm = b''.join(struct.pack('<3f', *v) for v in verts)
    doc['bufferViews'].append({'buffer': 0, 'byteOffset': len(buf), 'byteLength': len(nrm)})
    doc['accessors'].append({'bufferView': len(doc['bufferViews']) - 1, 'componentType': 5126,
                             'count': len(verts), 'type': 'VEC3'})
    doc['meshes'][0]['primitives'][0]['attributes']['NORMAL'] = len(doc['accessors']) - 1
    buf += nrm
    doc['buffers'][0]['byteLength'] = len(buf)
    write_gltf(os.path.join(out, 'sphere_n.gltf'), doc, buf)
    # the leaning quad: normals 60 degrees from +z towards +x
    n = (math.sin(math.pi / 3), 0.0, math.cos(math.pi / 3))
    s = ''.join('v %g %g 0\n' % p for p in ((-10, -10), (10, -10), (10, 10), (-10, 10)))
    s += 'vn %r %r %r\nf 1//1 2//1 3//1\nf 1//1 3//1 4//1\n' % n
    w(os.path.join(out, 'tilt.obj'), s)
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests', 'data',
                           'scenes', 'conductor_box.scene')) as f:
        box = f.read()
    box += ('\n# a smooth conductor sphere (left, mirror) and a smooth diffuse one (right)\n'
            'mesh sphere_n.obj material tall_box scale 0.08 translate 0.17 0.5 0.2\n'
            'mesh sphere_n.ply material white smooth scale 0.07 translate 0.38 0.35 0.12\n')
    w(os.path.join(out, 'smooth_box.scene'), box)
    glass = ('\n# smooth spheres (sphere_n.obj): clear and rough glass at the back, a smooth\n'
             '# and a rough coating in front\n'
             'material clear dielectric ior 1.5\nmaterial frosted dielectric ior 1.5 alpha 0.3\n'
             'material paint coated reflect red ior 1.5\n'
             'material satin coated reflect green ior 1.5 alpha 0.2\n'
             'mesh sphere_n.obj material clear scale 0.08 translate 0.15 0.3 0.35\n'
             'mesh sphere_n.obj material frosted scale 0.08 translate 0.38 0.3 0.35\n'
             'mesh sphere_n.obj material paint scale 0.07 translate 0.17 0.4 0.15\n'
             'mesh sphere_n.obj material satin scale 0.07 translate 0.40 0.4 0.15\n')
    w(os.path.join(out, 'smooth_glass_box.scene'), box + glass)
    write_sphere_ply(os.path.join(out, 'sphere_fine.ply'), 48, 96)
    w(os.path.join(out, 'invisible.scene'),
      '# a smooth clear glass sphere in a uniform background: invisible\n'
      'image 32 32\ncamera position 0 0 -4  direction 0 0 1  fov 32\n'
      'spectrum e inline 380 1 780 1 end\nbackground both e 1\n'
      'material clear dielectric ior 1.5\nmesh sphere_fine.ply material clear\n')
    w(os.path.join(out, 'invisible_coarse.scene'),
      '# invisible.scene with the sphere of 224 triangles\n'
      'image 32 32\ncamera position 0 0 -4  direction 0 0 1  fov 32\n'
      'spectrum e inline 380 1 780 1 end\nbackground both e 1\n'
      'material clear dielectric ior 1.5\nmesh sphere_n.ply material clear\n')
    leak = ('# tilt.obj (smooth, its normals lean 60 degrees) seen from its front face;\n'
            '# behind it a white wall, lit by a light between the two (facing the wall)\n'
            'image 16 16\ncamera position 0 0 5  direction 0 0 -1  fov 30\n'
            'spectrum white inline 380 0.8 780 0.8 end\nspectrum e inline 380 1 780 1 end\n'
            'material wall reflect white\nmaterial light emit e 100\n'
            'material mirror conductor e e\nmaterial rough conductor e e alpha 0.3\n'
            'material paint coated reflect white ior 1.5\n'
            'material satin coated reflect white ior 1.5 alpha 0.3\n'
            'quad wall -20 -20 -2  20 -20 -2  20 20 -2  -20 20 -2\n')
    light_back = 'quad light -1 -1 -1  -1 1 -1  1 1 -1  1 -1 -1\n'  # faces -z: the wall
    light_front = 'quad light 2 -1 3  2 1 3  4 1 3  4 -1 3\n'      # faces -z: the quad
    for name, light in (('leak', light_back), ('leak_lit', light_front)):
        for kind, mat, clause in (('diffuse', 'wall', 'smooth'), ('rough', 'rough', ''),
                                  ('mirror', 'mirror', ''), ('paint', 'paint', ''),
                                  ('satin', 'satin', '')):
            sc = leak + light + 'mesh tilt.obj material %s %s\n' % (mat, clause)
            w(os.path.join(out, '%s_%s.scene' % (name, kind)), sc)


def big(out, n):
    """A bumpy sphere of about n triangles, binary PLY, radius about 1."""
    rings = max(4, int(math.sqrt(n / 2)))
    segs = max(4, n // (2 * rings))
    verts = []
    for i in range(rings + 1):
        th = math.pi * i / rings
        for j in range(segs):
            ph = 2 * math.pi * j / segs
            r = 1.0 + 0.05 * math.sin(7 * th) * math.cos(5 * ph)
            verts.append((r * math.sin(th) * math.cos(ph), r * math.cos(th),
                          r * math.sin(th) * math.sin(ph)))
    faces = []
    for i in range(rings):
        for j in range(segs):
            a, b = i * segs + j, i * segs + (j + 1) % segs
            c, d = a + segs, b + segs
            faces += [(a, b, d), (a, d, c)]  # the poles' rings give degenerate ones
    with open(os.path.join(out, 'big.ply'), 'wb') as f:
        f.write(ply_header('binary_little_endian', len(verts), 'face', len(faces)).encode())
        f.write(b''.join(struct.pack('<3f', *p) for p in verts))
        f.write(b''.join(struct.pack('<B3i', 3, *t) for t in faces))
    big_scenes(out, verts, faces, rings, segs)
    return len(faces)


def big_scenes(out, verts, faces, rings, segs):
    """The sphere in the Cornell box, as a mesh statement and as text."""
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, '..', 'scenes', 'cornell.scene')) as f:
        box = f.read()
    scale, shift = 0.12, (0.28, 0.2, 0.3)
    w(os.path.join(out, 'big.scene'),
      box + 'mesh big.ply material white scale %g translate %g %g %g\n' % ((scale,) + shift))
    lines = [box]
    for k, t in enumerate(faces):
        ring, first = (k // 2) // segs, k % 2 == 0
        if (ring == 0 and first) or (ring == rings - 1 and not first):
            continue  # a pole triangle: two corners coincide
        p = [struct.unpack('<3f', struct.pack('<3f', *verts[i])) for i in t]
        lines.append('tri white ' + '  '.join(' '.join('%.9g' % (c * scale + o)
                                                       for c, o in zip(v, shift)) for v in p))
    w(os.path.join(out, 'big_text.scene'), '\n'.join(lines) + '\n')


FACE = struct.Struct('<B3i')


def write_ply(path, verts, faces):
    """verts: flat list of floats (xyz ...); faces: list of index triples."""
    with open(path, 'wb') as f:
        f.write(ply_header('binary_little_endian', len(verts) // 3, 'face', len(faces)).encode())
        f.write(struct.pack('<%df' % len(verts), *verts))
        f.write(b''.join(FACE.pack(3, *t) for t in faces))


def grid_shape(n, point, wrap_u):
    """A (u, v) grid of about n triangles, closed in v (and in u with wrap_u);
    point(u, v) for u, v in [0, 1] -> xyz."""
    rows = max(4, int(math.sqrt(n / 2)))
    cols = max(4, n // (2 * rows))
    verts = []
    for i in range(rows + (0 if wrap_u else 1)):
        for j in range(cols):
            verts += point(i / rows, j / cols)
    nrow = len(verts) // (3 * cols)
    faces = []
    for i in range(rows):
        for j in range(cols):
            a, b = i * cols + j, i * cols + (j + 1) % cols
            c, d = ((i + 1) % nrow) * cols + j, ((i + 1) % nrow) * cols + (j + 1) % cols
            faces += [(a, b, d), (a, d, c)]
    return verts, faces


def sphere_point(u, v):
    th, ph = math.pi * (0.02 + 0.96 * u), 2 * math.pi * v  # open at the poles: no slivers
    r = 1.0 + 0.05 * math.sin(7 * th) * math.cos(5 * ph)
    return (r * math.sin(th) * math.cos(ph), r * math.cos(th), r * math.sin(th) * math.sin(ph))


def torus_point(u, v):
    a, b = 2 * math.pi * u, 2 * math.pi * v
    r = 0.5 + 0.03 * math.sin(9 * a) * math.cos(4 * b)
    return ((2 + r * math.cos(b)) * math.cos(a), r * math.sin(b), (2 + r * math.cos(b)) * math.sin(a))


def soup(n):
    import random
    rnd = random.Random(n)
    size = 4.0 / max(1.0, n ** (1 / 3))  # about as many triangles along a ray at every n
    verts, faces = [], []
    for k in range(n):
        c = [rnd.uniform(-1, 1) for _ in range(3)]
        for _ in range(3):
            verts += [c[i] + rnd.uniform(-size, size) for i in range(3)]
        faces.append((3 * k, 3 * k + 1, 3 * k + 2))
    return verts, faces


# camera, light quad (A B C D, facing down) per shape
SCALE_SCENES = {
    'sphere': ('position 0 -0.3 -0.5  direction 0 0 1  fov 60',
               '-0.2 0.8 -0.2  0.2 0.8 -0.2  0.2 0.8 0.2  -0.2 0.8 0.2'),
    'torus': ('position 2 0 0  direction -0.3 0 1  fov 50',
              '1.9 0.4 -0.1  2.1 0.4 -0.1  2.1 0.4 0.1  1.9 0.4 0.1'),
    'soup': ('position 0 0 -2.2  direction 0 0 1  fov 50',
             '-0.5 1.3 -0.5  0.5 1.3 -0.5  0.5 1.3 0.5  -0.5 1.3 0.5'),
}


def scale_mesh(shape, n, ply, scene):
    if shape == 'soup':
        verts, faces = soup(n)
    else:
        verts, faces = grid_shape(n, sphere_point if shape == 'sphere' else torus_point,
                                  shape == 'torus')
    write_ply(ply, verts, faces)
    cam, light = SCALE_SCENES[shape]
    w(scene, '# %s of %d triangles, generated by tools/gen_meshes.py --scale\n'
             'image 256 256\nspp 4\ncamera %s\n'
             'spectrum white equal\nspectrum lamp file illuminant_D65.csv\n'
             'material paint reflect white 0.7\nmaterial lamp emit lamp 50\n'
             'quad lamp %s\nmesh %s material paint\n'
             % (shape, len(faces), cam, light, os.path.basename(ply)))
    return len(faces)


# ---- conductor scenes -------------------------------------------------------

def outward(c, tri):
    """tri with its front face, (v1 - v0) x (v2 - v0), away from the point c."""
    p, q, r = tri
    e1 = [q[k] - p[k] for k in range(3)]
    e2 = [r[k] - p[k] for k in range(3)]
    n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
         e1[0] * e2[1] - e1[1] * e2[0])
    g = [(p[k] + q[k] + r[k]) / 3 - c[k] for k in range(3)]
    return tri if sum(n[k] * g[k] for k in range(3)) > 0 else (p, r, q)


def sphere_mesh(mat, c, r):
    """A smooth sphere of centre c and radius r: materials_sphere.ply (a unit
    sphere of 528 triangles with its vertex normals, bundled beside the scenes)."""
    return 'mesh materials_sphere.ply material %s scale %g translate %g %g %g\n' % (mat, r, *c)


def uv_sphere(c, r, rings=4, segs=8):
    """A sphere of 2 segs (rings - 1) triangles: poles as single vertices."""
    def pt(i, j):
        th, ph = math.pi * i / rings, 2 * math.pi * (j + 0.5 * (i % 2)) / segs
        return (c[0] + r * math.sin(th) * math.cos(ph), c[1] + r * math.cos(th),
                c[2] + r * math.sin(th) * math.sin(ph))
    tris = []
    for i in range(rings):
        for j in range(segs):
            a, b = pt(i, j), pt(i, j + 1)
            cc, d = pt(i + 1, j), pt(i + 1, j + 1)
            if i > 0:
                tris.append((a, b, d) if i % 2 == 0 else (a, b, cc))
            if i < rings - 1:
                tris.append((a, d, cc) if i % 2 == 0 else (b, d, cc))
    return [outward(c, t) for t in tris]


def block(cx, cz, half, height, deg):
    """A block standing on the floor (y = 0), square footprint 2 half, turned deg
    about y: the top and four sides (the floor hides the bottom), 10 triangles."""
    a = math.radians(deg)
    corners = [(cx + half * (u * math.cos(a) - v * math.sin(a)), cz + half * (u * math.sin(a) +
                v * math.cos(a))) for u, v in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    lo = [(x, 0.0, z) for x, z in corners]
    hi = [(x, height, z) for x, z in corners]
    quads = [hi] + [(lo[k], lo[(k + 1) % 4], hi[(k + 1) % 4], hi[k]) for k in range(4)]
    c = (cx, 0.5 * height, cz)
    tris = []
    for q in quads:
        tris += [outward(c, (q[0], q[1], q[2])), outward(c, (q[0], q[2], q[3]))]
    return tris


def tri_lines(material, tris):
    return ''.join('tri %-11s %s\n' % (material, '  '.join(' '.join('%.6f' % x for x in v)
                                                        for v in t)) for t in tris)


# cornell.scene's colours: its walls' ColorChecker spectra and its equal-energy
# light, with their materials (the light of luminance EMIT)
CORNELL_SPECTRA = """spectrum white     file colorchecker_n_ohta.csv column white_9_5
spectrum red       file colorchecker_n_ohta.csv column red
spectrum green     file colorchecker_n_ohta.csv column green
spectrum equal     equal
"""


def cornell_materials(emit):
    return ('material white     reflect white\nmaterial red       reflect red\n'
            'material green     reflect green\nmaterial light     reflect white  emit equal %g\n' % emit)


ROOM = """# room: floor, back wall, left (red) wall, right (green) wall, ceiling
quad white  0.556 0.000 0.000  0.003 0.000 0.000  0.006 0.000 0.559  0.556 0.000 0.559
quad white  0.556 0.000 0.559  0.006 0.000 0.559  0.000 0.549 0.559  0.556 0.549 0.559
quad %s    0.006 0.000 0.559  0.003 0.000 0.000  0.000 0.549 0.000  0.000 0.549 0.559
quad %s  0.556 0.000 0.000  0.556 0.000 0.559  0.556 0.549 0.559  0.556 0.549 0.000
quad white  0.556 0.549 0.559  0.000 0.549 0.559  0.000 0.549 0.000  0.556 0.549 0.000

# light, just below the ceiling, facing down (emitters emit from the front face:
# the normal (b - a) x (c - a) points to -y)
quad light  0.343 0.545 0.332  0.213 0.545 0.332  0.213 0.545 0.227  0.343 0.545 0.227
"""

METALS_HEAD = """# Metals: the Cornell box of cornell.scene (its walls, camera and equal-energy
# light of luminance 1000) with measured conductors in place of its two boxes:
# at the back, smooth (mirror) blocks of gold, copper and aluminium; in front,
# rough spheres (GGX, alpha 0.2) of the same metals. Their colours come from
# the complex index of refraction eta + i k per wavelength (spectra/metal_*:
# LuxPop data), so they change with the angle of incidence. The spheres are
# smooth (materials_sphere.ply, with its vertex normals); docs/MATERIALS.md's
# and docs/VALIDATION.md's measurements were made when they were faceted
# (8 x 4 UV spheres). The objects are written by tools/gen_meshes.py --metals (do not edit them here: regenerate);
# bench/peers/mitsuba_compare.py renders it with Mitsuba 3 as a check of truth.
# Format: docs/SCENE_FORMAT.md.

image 256 256
spp 64
camera position 0.278 0.275 -0.789  direction 0 0 1  fov 40

""" + CORNELL_SPECTRA

SODIUM_HEAD = """# Copper under sodium light - where rgb breaks on a metal. The Cornell box of
# cornell.scene, all walls ColorChecker white, lit only by the NIST low-pressure
# sodium lamp: one line at 590 nm (585-595 nm at its 5 nm sampling). In it
# stand a smooth copper block, a rough copper sphere (GGX, alpha 0.2) and a
# white (Lambertian) block for comparison. Copper's reflectance climbs steeply
# across the line's neighbourhood (normal incidence: 0.66 at 560, 0.81 at
# 589, 0.91 at 620 nm), but inside a single line a reflection can only dim the
# light, not change its chromaticity:
#  - truth, ref, ml, mlc, hero: the copper looks the lamp's yellow, like the
#    white block, only darker (its reflectance at 590 nm, about 0.81, at normal
#    incidence);
#  - rgb is wrong: it multiplies three channels, copper's D65-referred RGB
#    (about 0.95, 0.64, 0.54) times the lamp's linear sRGB, which for a
#    spectral line lies outside the sRGB gamut (a negative blue); a product
#    per channel moves the chromaticity, so the copper comes out redder than
#    the white block: on the same paths (128 px wide, 256 spp) rgb is 4.6
#    dE00 off truth on the smooth copper block (1.4 over the whole image),
#    where ref, ml and mlc stay below 0.35;
#  - ml at a coarse level would average eta and k over a 20 nm bin (580-600 nm)
#    across the copper edge: the pretest has to see that the Fresnel of the
#    bin means is not the mean Fresnel under the line.
# The objects are written by tools/gen_meshes.py --metals. Format:
# docs/SCENE_FORMAT.md.

image 256 256
spp 64
camera position 0.278 0.275 -0.789  direction 0 0 1  fov 40

spectrum white     file colorchecker_n_ohta.csv column white_9_5
spectrum lps       file lightsource_nist_lps.csv
"""

METAL_DATA = {'gold': 'Au', 'copper': 'Cu', 'aluminium': 'Al'}


def metal_spectra(names):
    s = ''
    for m in names:
        sym = METAL_DATA[m]
        s += 'spectrum %-9s file metal_%s_eta.csv\n' % (sym.lower() + '_eta', sym)
        s += 'spectrum %-9s file metal_%s_k.csv\n' % (sym.lower() + '_k', sym)
    return s


def metal_materials(names, alpha):
    s = ''
    for m in names:
        sym = METAL_DATA[m].lower()
        s += 'material %-15s conductor %s_eta %s_k\n' % (m + '_smooth', sym, sym)
        s += 'material %-15s conductor %s_eta %s_k alpha %g\n' % (m + '_rough', sym, sym, alpha)
    return s


def metals_scenes(out):
    """Writes metals.scene and copper_sodium.scene into out; returns their paths."""
    names = ('gold', 'copper', 'aluminium')
    s = METALS_HEAD + metal_spectra(names) + '\n'
    s += cornell_materials(1000)
    s += metal_materials(names, 0.2) + '\n' + ROOM % ('red', 'green')
    s += '\n# smooth blocks at the back: gold (tall, left), copper, aluminium (short, right)\n'
    for m, x, h, deg in (('gold', 0.125, 0.30, 40), ('copper', 0.28, 0.22, -45),
                         ('aluminium', 0.435, 0.16, 50)):
        s += tri_lines(m + '_smooth', block(x, 0.42, 0.055, h, deg))
    s += '\n# rough spheres in front, on the floor: gold (left), copper, aluminium (right)\n'
    for m, x in (('gold', 0.13), ('copper', 0.28), ('aluminium', 0.43)):
        s += sphere_mesh(m + '_rough', (x, 0.06, 0.17), 0.06)
    paths = [os.path.join(out, 'metals.scene'), os.path.join(out, 'copper_sodium.scene')]
    w(paths[0], s)
    s = SODIUM_HEAD + metal_spectra(('copper',)) + '\n'
    s += 'material white     reflect white\nmaterial light     reflect white  emit lps 1000\n'
    s += metal_materials(('copper',), 0.2) + '\n' + ROOM % ('white', 'white')
    s += '\n# a smooth copper block (left), a white block (right), a rough copper sphere (front)\n'
    s += tri_lines('copper_smooth', block(0.17, 0.38, 0.07, 0.22, 45))
    s += tri_lines('white', block(0.40, 0.38, 0.07, 0.22, -20))
    s += tri_lines('copper_rough', uv_sphere((0.28, 0.08, 0.15), 0.08))
    w(paths[1], s)
    return paths


COATED_HEAD = """# Coatings: the Cornell box of cornell.scene (its walls, camera and equal-energy
# light of luminance 1000) with coated objects, a Lambertian base under a
# dielectric coating (docs/METHODS.md "Coatings", Mitsuba 3's plastic and
# roughplastic with nonlinear internal reflections): at the back, a smooth red
# plastic block (index 1.5), a rough blue paint block (index 1.5, GGX alpha
# 0.1) and a smooth white glaze block (index 1.6); in front, spheres of rough
# yellow paint (alpha 0.3), smooth blue and rough red plastic (alpha 0.05). The
# objects are written by tools/gen_meshes.py --coated (do not edit them here:
# regenerate); bench/peers/mitsuba_compare.py renders it with Mitsuba 3 as a
# check of truth. Format: docs/SCENE_FORMAT.md.

image 256 256
spp 64
camera position 0.278 0.275 -0.789  direction 0 0 1  fov 40

spectrum white     file colorchecker_n_ohta.csv column white_9_5
spectrum red       file colorchecker_n_ohta.csv column red
spectrum green     file colorchecker_n_ohta.csv column green
spectrum blue      file colorchecker_n_ohta.csv column blue
spectrum yellow    file colorchecker_n_ohta.csv column yellow
spectrum equal     equal
"""

COATED_SPIKY_HEAD = """# Saturated coated paints under a tri-band lamp - where rgb breaks on a
# coating. The Cornell box of cornell.scene, all walls ColorChecker white, lit
# only by CIE F11 (three narrow phosphor bands near 435, 545 and 610 nm). In
# it stand smooth coated blocks of ColorChecker magenta, cyan and
# orange-yellow (index 1.5) and a rough coated magenta sphere (alpha 0.2).
# The coating's effective base colour D = R (1 - Fdr_i) / (1 - Fdr_i R) is
# nonlinear in R per wavelength and saturated paints have steep edges right
# where F11's bands sit, so a product of three channels (rgb: the RGB of D
# under D65 times the lamp's RGB) misses what the bands pick out of the
# spectrum, and the interreflections multiply the error; the spectral modes
# shade D per bin. On the same paths (128 x 128 px, 64 spp, seed 1) rgb is
# 2.9 dE00 off truth at the 99th percentile (mean 0.39, max 3.4), where ref
# stays at 0.08 and ml (T = 1 or 2) at 0.30 (README "Materials"). The objects
# are written by tools/gen_meshes.py --coated. Format: docs/SCENE_FORMAT.md.

image 256 256
spp 64
camera position 0.278 0.275 -0.789  direction 0 0 1  fov 40

spectrum white     file colorchecker_n_ohta.csv column white_9_5
spectrum magenta   file colorchecker_n_ohta.csv column magenta
spectrum cyan      file colorchecker_n_ohta.csv column cyan
spectrum orange    file colorchecker_n_ohta.csv column orange_yellow
spectrum f11       file illuminant_F11.csv
"""


def coated_scenes(out):
    """Writes coated.scene and coated_spiky.scene into out; returns their paths."""
    s = COATED_HEAD + '\n'
    s += cornell_materials(1000) + (
        'material red_plastic   coated reflect red ior 1.5\n'
        'material blue_paint    coated reflect blue ior 1.5 alpha 0.1\n'
        'material white_glaze   coated reflect white ior 1.6\n'
        'material yellow_paint  coated reflect yellow ior 1.5 alpha 0.3\n'
        'material blue_plastic  coated reflect blue ior 1.5\n'
        'material red_rough     coated reflect red ior 1.5 alpha 0.05\n')
    s += '\n' + ROOM % ('red', 'green')
    s += '\n# blocks at the back: red plastic (tall, left), blue paint, white glaze (short, right)\n'
    for m, x, h, deg in (('red_plastic', 0.125, 0.30, 40), ('blue_paint', 0.28, 0.22, -45),
                         ('white_glaze', 0.435, 0.16, 50)):
        s += tri_lines(m, block(x, 0.42, 0.055, h, deg))
    s += '\n# spheres in front, on the floor: yellow paint (left), blue plastic, red (right)\n'
    for m, x in (('yellow_paint', 0.13), ('blue_plastic', 0.28), ('red_rough', 0.43)):
        s += tri_lines(m, uv_sphere((x, 0.06, 0.17), 0.06))
    paths = [os.path.join(out, 'coated.scene'), os.path.join(out, 'coated_spiky.scene')]
    w(paths[0], s)
    s = COATED_SPIKY_HEAD + '\n'
    s += ('material white     reflect white\nmaterial light     reflect white  emit f11 1000\n'
          'material magenta_coat  coated reflect magenta ior 1.5\n'
          'material cyan_coat     coated reflect cyan ior 1.5\n'
          'material orange_coat   coated reflect orange ior 1.5\n'
          'material magenta_rough coated reflect magenta ior 1.5 alpha 0.2\n')
    s += '\n' + ROOM % ('white', 'white')
    s += '\n# smooth blocks: magenta (left), cyan, orange-yellow (right); a rough magenta sphere\n'
    for m, x, h, deg in (('magenta_coat', 0.125, 0.30, 40), ('cyan_coat', 0.28, 0.22, -45),
                         ('orange_coat', 0.435, 0.16, 50)):
        s += tri_lines(m, block(x, 0.42, 0.055, h, deg))
    s += tri_lines('magenta_rough', uv_sphere((0.28, 0.08, 0.15), 0.08))
    w(paths[1], s)
    return paths


def closed_block(cx, y0, cz, half, height, deg):
    """A closed block (glass needs an inside): block()'s top and sides lifted to
    y0, and its bottom, 12 triangles, every front face outward."""
    tris = [tuple((x, y + y0, z) for x, y, z in t) for t in block(cx, cz, half, height, deg)]
    a = math.radians(deg)
    lo = [(cx + half * (u * math.cos(a) - v * math.sin(a)), y0, cz + half * (u * math.sin(a) +
           v * math.cos(a))) for u, v in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    c = (cx, y0 + 0.5 * height, cz)
    return tris + [outward(c, (lo[0], lo[1], lo[2])), outward(c, (lo[0], lo[2], lo[3]))]


GLASS_HEAD = """# Glass: the Cornell box of cornell.scene (its walls, camera and equal-energy
# light of luminance 1000) with dielectrics of index 1.5 in place of its two
# boxes: at the back, a white (Lambertian) block behind a clear glass block
# and a green, absorbing glass block (Beer-Lambert, 'absorb greenabs 12': a
# transmittance exp(-12 greenabs(lambda) d) over d scene units, about 0.3 of
# the red through its 0.11 width); in front, a smooth clear sphere (left) and
# a rough one (GGX, alpha 0.2, right), smooth (materials_sphere.ply, with
# its vertex normals; docs/MATERIALS.md's and docs/VALIDATION.md's
# measurements were made when they were faceted, 72 triangles each). Objects
# float 1 mm above the floor so no glass face touches another surface
# (docs/SCENE_FORMAT.md: dielectric). Written by
# tools/gen_meshes.py --glass (do not edit the objects here: regenerate);
# bench/peers/mitsuba_compare.py renders it with Mitsuba 3 as a check of truth.
# Format: docs/SCENE_FORMAT.md.

image 256 256
spp 64
camera position 0.278 0.275 -0.789  direction 0 0 1  fov 40

""" + CORNELL_SPECTRA + """spectrum greenabs  inline 380 1.0 450 0.7 500 0.1 540 0.02 580 0.1 630 0.8 700 1.0 780 1.0 end
"""

DEEP_HEAD = """# Deep-coloured glass - where rgb breaks on a dielectric. The Cornell box of
# cornell.scene, walls ColorChecker white, equal-energy light, with two thick
# glass blocks (index 1.5) of a filter glass that passes only a narrow band
# around 600 nm and absorbs strongly elsewhere ('absorb notch 60': exp(-60 d)
# outside the band over d scene units, e^-6 through the blocks' 0.1 width),
# and a white block for comparison. Beer-Lambert is not linear in the
# absorption: truth, ref, ml and mlc exponentiate it per wavelength, so the
# band shines through orange; rgb exponentiates the absorption's mean over
# each channel (exp(-d sigma_rgb)), and every channel's mean is dominated by
# the absorbing part, so its glass comes out a dark brown-red: on the same
# paths (96 px wide, 32 spp) rgb is 11.5 dE00 off truth at the 99th
# percentile, where ml (the pretest picks 1 nm for this absorption) is 0.25.
# The objects are written by tools/gen_meshes.py --glass. Format:
# docs/SCENE_FORMAT.md.

image 256 256
spp 64
camera position 0.278 0.275 -0.789  direction 0 0 1  fov 40

spectrum white     file colorchecker_n_ohta.csv column white_9_5
spectrum equal     equal
spectrum notch     inline 380 1.0 585 1.0 592 0.0 608 0.0 615 1.0 780 1.0 end
"""


def glass_scenes(out):
    """Writes glass.scene and glass_deep.scene into out; returns their paths."""
    s = GLASS_HEAD + '\n'
    s += cornell_materials(1000) + (
        'material clear     dielectric ior 1.5\n'
        'material greenglass dielectric ior 1.5 absorb greenabs 12\n'
        'material rough     dielectric ior 1.5 alpha 0.2\n')
    s += '\n' + ROOM % ('red', 'green')
    s += '\n# at the back: a white block behind a clear block (left), a green glass block (right)\n'
    s += tri_lines('white', block(0.16, 0.47, 0.05, 0.30, 30))
    s += tri_lines('clear', closed_block(0.17, 0.001, 0.33, 0.055, 0.20, -20))
    s += tri_lines('greenglass', closed_block(0.40, 0.001, 0.40, 0.055, 0.25, 25))
    s += '\n# in front: a smooth clear sphere (left), a rough one (right)\n'
    s += sphere_mesh('clear', (0.16, 0.071, 0.15), 0.07)
    s += sphere_mesh('rough', (0.40, 0.071, 0.15), 0.07)
    paths = [os.path.join(out, 'glass.scene'), os.path.join(out, 'glass_deep.scene')]
    w(paths[0], s)
    s = DEEP_HEAD + '\n'
    s += ('material white     reflect white\nmaterial light     reflect white  emit equal 1000\n'
          'material filter    dielectric ior 1.5 absorb notch 60\n')
    s += '\n' + ROOM % ('white', 'white')
    s += '\n# two filter-glass blocks (left, front right) and a white block (back right)\n'
    s += tri_lines('filter', closed_block(0.17, 0.001, 0.30, 0.05, 0.25, 30))
    s += tri_lines('filter', closed_block(0.36, 0.001, 0.18, 0.05, 0.12, -15))
    s += tri_lines('white', block(0.40, 0.42, 0.06, 0.22, -20))
    w(paths[1], s)
    return paths


def pbr_meshes(out):
    quads = []
    for i in range(5):
        quads += [(2 * i, 0, 0), (2 * i + 1, 0, 0), (2 * i + 1, 1, 0), (2 * i, 1, 0)]
    def glass(name, t, rough, base=(1, 1, 1), ext=None):
        m = {'name': name, 'pbrMetallicRoughness': {'baseColorFactor': list(base) + [1.0],
                                                    'metallicFactor': 0.0, 'roughnessFactor': rough},
             'extensions': {'KHR_materials_transmission': {'transmissionFactor': t}}}
        m['extensions'].update(ext or {})
        return m
    mats = [glass('solid', 1.0, 0.3, ext={'KHR_materials_ior': {'ior': 1.33},
                                           'KHR_materials_volume': {
                                               'thicknessFactor': 0.5,
                                               'attenuationColor': [0.9, 0.5, 0.2],
                                               'attenuationDistance': 2.0}}),
            glass('thin', 1.0, 0.0),
            glass('part', 0.7, 0.1),
            glass('low', 0.3, 0.0, base=(0.3, 0.6, 0.3)),
            {'name': 'plastic', 'pbrMetallicRoughness': {'baseColorFactor': [0.2, 0.4, 0.8, 1.0],
                                                         'metallicFactor': 0.0,
                                                         'roughnessFactor': 0.6},
             'extensions': {'KHR_materials_ior': {'ior': 1.7}}}]
    prims = [([4 * i, 4 * i + 1, 4 * i + 2, 4 * i, 4 * i + 2, 4 * i + 3], i) for i in range(5)]
    doc, buf = gltf_doc(quads, prims, [{'mesh': 0}], [0], mats)
    doc['extensionsUsed'] = ['KHR_materials_transmission', 'KHR_materials_ior',
                             'KHR_materials_volume']
    write_gltf(os.path.join(out, 'pbr.gltf'), doc, buf)
    w(os.path.join(out, 'pbr.mtl'), 'newmtl paint\nKd 0.5 0.1 0.1\nKs 0.04 0.04 0.04\nNs 50\n'
      'Ni 1.6\nillum 2\n\nnewmtl glass\nKd 0 0 0\nKs 1 1 1\nNs 1000\nNi 1.45\nillum 7\n\n'
      'newmtl veil\nKd 0.5 0.5 0.5\nd 0.5\nillum 1\n')
    w(os.path.join(out, 'pbr.obj'), 'mtllib pbr.mtl\n' +
      ''.join('v %d 0 0\nv %d 0 0\nv %d 1 0\nv %d 1 0\n' % (2 * i, 2 * i + 1, 2 * i + 1, 2 * i)
              for i in range(3)) +
      ''.join('usemtl %s\nf %d %d %d %d\n' % (m, 4 * i + 1, 4 * i + 2, 4 * i + 3, 4 * i + 4)
              for i, m in enumerate(('paint', 'glass', 'veil'))))
    verts, tris = sphere_n()
    pos = [(x - 1.2, y, z) for x, y, z in verts] + [(x + 1.2, y, z) for x, y, z in verts]
    nv = len(verts)
    prims = [([i for t in tris for i in t], 0), ([i + nv for t in tris for i in t], 1)]
    mats = [glass('amber', 1.0, 0.0, ext={'KHR_materials_volume': {
                'thicknessFactor': 2.0, 'attenuationColor': [0.9, 0.6, 0.2],
                'attenuationDistance': 1.0}}),
            {'name': 'paint', 'pbrMetallicRoughness': {'baseColorFactor': [0.7, 0.15, 0.1, 1.0],
                                                       'metallicFactor': 0.0,
                                                       'roughnessFactor': 0.3}}]
    doc, buf = gltf_doc(pos, prims, [{'mesh': 0}], [0], mats)
    doc['extensionsUsed'] = ['KHR_materials_transmission', 'KHR_materials_volume']
    write_gltf(os.path.join(out, 'pbr_spheres.gltf'), doc, buf)


MATERIALS_HEAD = """# Materials: the Cornell box of cornell.scene (its walls, camera and
# equal-energy light of luminance 1000) with one sphere of each type on
# smooth shading normals: at the back, gold (left; measured eta + i k,
# spectra/metal_Au_*) and a red plastic coating (right, index 1.5); in front,
# clear glass (left), green absorbing glass (middle, 'absorb greenabs 12' as
# in glass.scene) and rough glass (right, GGX alpha 0.2), all of index 1.5.
# Each sphere is materials_sphere.ply (528 triangles with vertex normals) scaled
# and placed by its mesh statement; conductors, glass and coatings shade a
# mesh's vertex normals by default (docs/SCENE_FORMAT.md). They float 1 mm
# above the floor so no glass face touches another surface. Written by
# tools/gen_meshes.py --materials (do not edit: regenerate);
# bench/peers/mitsuba_compare.py renders it with Mitsuba 3 as a check of truth.
# Format: docs/SCENE_FORMAT.md.

image 256 256
spp 64
camera position 0.278 0.275 -0.789  direction 0 0 1  fov 40

spectrum white     file colorchecker_n_ohta.csv column white_9_5
spectrum red       file colorchecker_n_ohta.csv column red
spectrum green     file colorchecker_n_ohta.csv column green
spectrum equal     equal
spectrum au_eta    file metal_Au_eta.csv
spectrum au_k      file metal_Au_k.csv
spectrum greenabs  inline 380 1.0 450 0.7 500 0.1 540 0.02 580 0.1 630 0.8 700 1.0 780 1.0 end
"""


def materials_scene(out):
    """Writes materials.scene and materials_sphere.ply into out; returns their paths."""
    paths = [os.path.join(out, 'materials.scene'), os.path.join(out, 'materials_sphere.ply')]
    write_sphere_ply(paths[1], 12, 24)
    s = MATERIALS_HEAD + '\n'
    s += cornell_materials(1000) + (
        'material gold      conductor au_eta au_k\n'
        'material plastic   coated reflect red ior 1.5\n'
        'material clear     dielectric ior 1.5\n'
        'material greenglass dielectric ior 1.5 absorb greenabs 12\n'
        'material rough     dielectric ior 1.5 alpha 0.2\n')
    s += '\n' + ROOM % ('red', 'green')
    s += '\n# spheres: gold and plastic at the back; clear, green and rough glass in front\n'
    for mat, r, x, z in (('gold', 0.09, 0.15, 0.40), ('plastic', 0.09, 0.41, 0.40),
                         ('clear', 0.065, 0.12, 0.17), ('greenglass', 0.065, 0.28, 0.22),
                         ('rough', 0.065, 0.44, 0.17)):
        s += 'mesh materials_sphere.ply material %-10s scale %g translate %g %g %g\n' % (
            mat, r, x, r + 0.001, z)
    w(paths[0], s)
    return paths


PRISM_HEAD = """# Prism: the camera looks through a prism of Schott N-BK7 (apex angle 35
# degrees) at a thin slit of light behind it - eye, prism, light, so no
# caustic is needed. The front face is square to the view (the rays enter
# undeviated); the back face bends each wavelength its own way (n from 1.525
# at 450 nm to 1.515 at 650 nm), so the white slit is seen as a spectrum
# spread over about 11 pixels, blue farthest from the straight line (towards
# the prism's base). A path commits to one wavelength at the first glass
# face (docs/METHODS.md "Dispersion"), so every pixel sees its colour. No
# other light and no background. tests/cli_dispersion.sh checks the image
# position of 450, 550 and 650 nm against Snell's law. Written by
# tools/gen_meshes.py --dispersion (do not edit the objects here: regenerate).
# Format: docs/SCENE_FORMAT.md.

image 256 16
spp 256
camera position 0 0 0  direction 0 0 1  fov 10

spectrum equal  equal

material bk7   dielectric glass N-BK7
material slit  emit equal 100
"""

SPHERE_HEAD = """# An N-SF11 sphere in a room: the Cornell box of cornell.scene (its walls,
# camera and equal-energy light of luminance 1000) with a polished sphere of
# Schott N-SF11, a dense flint (n_d 1.785, Abbe number 25.7: n from 1.822 at
# 420 nm to 1.770 at 700 nm), in front of a white block. Its refraction
# fringes the edges of what is seen through it, and the light it focuses
# onto the floor (a caustic, reached by paths that hit the lamp through the
# glass) is split into colours. The sphere is smooth (materials_sphere.ply,
# with its vertex normals); docs/MATERIALS.md's measurements were made when
# it was faceted (an 8 x 12 UV sphere). Objects float 1 mm above
# the floor so no glass face touches another surface. Written by
# tools/gen_meshes.py --dispersion (do not edit the objects here: regenerate).
# Format: docs/SCENE_FORMAT.md.

image 256 256
spp 64
camera position 0.278 0.275 -0.789  direction 0 0 1  fov 40

""" + CORNELL_SPECTRA + "\n" + cornell_materials(1000) + """material sf11      dielectric glass N-SF11
"""

# the prism's geometry (tests/cli_dispersion.sh reads it back from the scene)
PRISM_APEX = 35.0
PRISM_Z, PRISM_HALF, PRISM_H = 1.0, 0.3, 0.5
SLIT_DIST, SLIT_HALF = 10.0, 0.002


def prism_tris():
    """The prism, axis along y: the front face z = PRISM_Z (x from -half to
    half), the back face at PRISM_APEX degrees to it (thickest at -x, the
    base), a side face at x = -half; outward-facing triangles."""
    a = math.radians(PRISM_APEX)
    p1 = (-PRISM_HALF, PRISM_Z)
    p2 = (PRISM_HALF, PRISM_Z)
    p3 = (-PRISM_HALF, PRISM_Z + 2 * PRISM_HALF * math.tan(a))
    c = ((p1[0] + p2[0] + p3[0]) / 3, 0.0, (p1[1] + p2[1] + p3[1]) / 3)
    lo = [(x, -PRISM_H, z) for x, z in (p1, p2, p3)]
    hi = [(x, PRISM_H, z) for x, z in (p1, p2, p3)]
    tris = [(lo[0], lo[1], lo[2]), (hi[0], hi[1], hi[2])]
    for k in range(3):
        j = (k + 1) % 3
        tris += [(lo[k], lo[j], hi[j]), (lo[k], hi[j], hi[k])]
    return [outward(c, t) for t in tris]


def slit_quad():
    """A vertical slit SLIT_DIST behind the back face's exit, along the ray
    that leaves it at 550 nm for the straight view, facing that ray."""
    a = math.radians(PRISM_APEX)
    n = 1.518522  # N-BK7 near 550 nm: only where the slit stands, not a check
    t = math.asin(n * math.sin(a))
    d = (math.sin(a - t), math.cos(a - t))  # the exit direction (x, z)
    zx = PRISM_Z + PRISM_HALF * math.tan(a)  # the back face at x = 0
    cx, cz = SLIT_DIST * d[0], zx + SLIT_DIST * d[1]
    u = (d[1], -d[0])  # across the slit
    h = 1.0
    q = [(cx - SLIT_HALF * u[0], -h, cz - SLIT_HALF * u[1]), (cx + SLIT_HALF * u[0], -h, cz + SLIT_HALF * u[1]),
         (cx + SLIT_HALF * u[0], h, cz + SLIT_HALF * u[1]), (cx - SLIT_HALF * u[0], h, cz - SLIT_HALF * u[1])]
    # front face towards the prism: (b - a) x (c - a) along -d
    e1 = [q[1][k] - q[0][k] for k in range(3)]
    e2 = [q[2][k] - q[0][k] for k in range(3)]
    nz = e1[0] * e2[1] - e1[1] * e2[0]
    nx = e1[1] * e2[2] - e1[2] * e2[1]
    if nx * d[0] + nz * d[1] > 0:
        q = [q[0], q[3], q[2], q[1]]
    return q


PRISM_WALL_HEAD = """# Prism on a wall: a narrow spot light (a cone of half-angle %(cone)g degrees)
# shines on a %(apex)g-degree prism of Schott N-SF11 (n from 1.819 at 450 nm
# to 1.777 at 650 nm) turned for minimum deviation at 550 nm, which throws
# the light's spectrum onto a white wall: 450 to 650 nm spread over 36
# pixels, violet farthest from the light's own direction. The camera looks at the
# wall only (the prism and the light are outside its view), so all it sees
# arrives through the glass from a point-like source: next-event estimation
# never finds it and a path tracer renders the wall black. Render it with
# --integrator light: each subpath commits to one wavelength at the first
# glass face (docs/METHODS.md "Dispersion"). tests/cli_light_prism.sh checks
# where 450, 550 and 650 nm fall on the wall against Snell's law. Written by
# tools/gen_meshes.py --dispersion (do not edit the objects here: regenerate).
# Format: docs/SCENE_FORMAT.md.

image 256 64
spp 64
camera position 0 0 0  direction 0 0 1  fov 30

spectrum equal  equal

material sf11  dielectric glass N-SF11
material wall  reflect equal 0.8
"""

# the prism on a wall: its centre (x, z), side, apex, the spot's distance to
# it and cone; the wall the plane z = WALL_Z (tests/cli_light_prism.sh reads
# all of it back from the scene)
PW_C, PW_SIDE, PW_APEX, PW_H = (-1.6, 2.0), 0.6, 60.0, 0.5
PW_LIGHT, PW_CONE, PW_OUT, WALL_Z = 1.5, 0.3, 62.0, 5.0


def prism_wall():
    """The prism's triangles and the spot light's line. In the prism's frame
    (u along the ray inside at minimum deviation, v towards the apex) the
    faces meet at the apex (0, side / sqrt 3) and the base corners
    (+-side / 2, -side / (2 sqrt 3)); the world's (x, z) is
    centre + R(rot) (u, -v), rot putting the 550 nm exit ray at PW_OUT
    degrees to +x; the light sits on the 550 nm entry ray, aimed at the
    entry face's midpoint (the ray inside then runs parallel to the base,
    halfway up)."""
    n = 1.791  # N-SF11 near 550 nm: only where things stand, not a check
    half = math.radians(PW_APEX / 2)
    dev = math.asin(n * math.sin(half)) - half  # each face's deviation
    rot = math.radians(PW_OUT) - dev
    r = PW_SIDE / math.sqrt(3)
    local = [(0.0, r), (-PW_SIDE / 2, -r / 2), (PW_SIDE / 2, -r / 2)]
    xz = [(PW_C[0] + u * math.cos(rot) + v * math.sin(rot),
           PW_C[1] + u * math.sin(rot) - v * math.cos(rot)) for u, v in local]
    lo = [(x, -PW_H, z) for x, z in xz]
    hi = [(x, PW_H, z) for x, z in xz]
    tris = [(lo[0], lo[1], lo[2]), (hi[0], hi[1], hi[2])]
    for k in range(3):
        j = (k + 1) % 3
        tris += [(lo[k], lo[j], hi[j]), (lo[k], hi[j], hi[k])]
    c = (PW_C[0], 0.0, PW_C[1])
    a = rot - dev  # the entry ray's direction, to the entry face's midpoint m
    m = ((xz[0][0] + xz[1][0]) / 2, (xz[0][1] + xz[1][1]) / 2)
    lx, lz = m[0] - PW_LIGHT * math.cos(a), m[1] - PW_LIGHT * math.sin(a)
    light = 'light spot %.6f 0 %.6f  %.6f 0 %.6f  equal intensity 80 cone %g falloff 0\n' % (
        lx, lz, m[0], m[1], PW_CONE)
    return [outward(c, t) for t in tris], light


def dispersion_scenes(out):
    paths = [os.path.join(out, 'prism.scene'), os.path.join(out, 'sf11_sphere.scene')]
    q = slit_quad()
    s = PRISM_HEAD + '\n# the prism\n' + tri_lines('bk7', prism_tris())
    s += '\n# the slit, facing the prism\nquad slit  %s\n' % '  '.join(
        ' '.join('%.6f' % x for x in v) for v in q)
    w(paths[0], s)
    s = SPHERE_HEAD + '\n' + ROOM % ('red', 'green') + '\n# at the back: a white block\n'
    s += tri_lines('white', block(0.36, 0.40, 0.07, 0.30, 25))
    s += '\n# in front: the N-SF11 sphere\n'
    s += sphere_mesh('sf11', (0.24, 0.111, 0.22), 0.11)
    w(paths[1], s)
    tris, light = prism_wall()
    wall = [(-3.0, -1.5, WALL_Z), (3.0, -1.5, WALL_Z), (3.0, 1.5, WALL_Z), (-3.0, 1.5, WALL_Z)]
    behind = (0.0, 0.0, WALL_Z + 1.0)
    s = PRISM_WALL_HEAD % {'cone': PW_CONE, 'apex': PW_APEX}
    s += '\n# the prism\n' + tri_lines('sf11', tris)
    s += '\n# the wall, facing the camera\n' + tri_lines(
        'wall', [outward(behind, (wall[0], wall[1], wall[2])), outward(behind, (wall[0], wall[2], wall[3]))])
    s += '\n# the spot light, aimed at the prism\n' + light
    paths.append(os.path.join(out, 'prism_wall.scene'))
    w(paths[2], s)
    return paths


def main():
    if len(sys.argv) == 3 and sys.argv[1] == '--dispersion':
        os.makedirs(sys.argv[2], exist_ok=True)
        print('\n'.join(dispersion_scenes(sys.argv[2])))
        return
    if len(sys.argv) == 3 and sys.argv[1] == '--materials':
        os.makedirs(sys.argv[2], exist_ok=True)
        print('\n'.join(materials_scene(sys.argv[2])))
        return
    if len(sys.argv) == 3 and sys.argv[1] == '--glass':
        os.makedirs(sys.argv[2], exist_ok=True)
        print('\n'.join(glass_scenes(sys.argv[2])))
        return
    if len(sys.argv) == 3 and sys.argv[1] == '--coated':
        os.makedirs(sys.argv[2], exist_ok=True)
        print('\n'.join(coated_scenes(sys.argv[2])))
        return
    if len(sys.argv) == 3 and sys.argv[1] == '--metals':
        os.makedirs(sys.argv[2], exist_ok=True)
        print('\n'.join(metals_scenes(sys.argv[2])))
        return
    if len(sys.argv) == 6 and sys.argv[1] == '--scale' and sys.argv[2] in SCALE_SCENES:
        print(scale_mesh(sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5]))
        return
    if len(sys.argv) < 2 or sys.argv[1].startswith('-'):
        sys.exit(__doc__)
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    obj(out)
    ply(out)
    stl(out)
    gltf(out)
    textured(out)
    grid(out)
    smooth_meshes(out)
    metal_meshes(out)
    pbr_meshes(out)
    write_tris(os.path.join(out, 'cube.tris'), [[V[i] for i in t[:3]] for t in TRIS])
    if len(sys.argv) > 2:
        print(big(out, int(sys.argv[2])))


if __name__ == '__main__':
    main()
