#!/usr/bin/env python3
"""Writes a textured glTF model (no dependencies beyond Python's standard library):
a square board of 4 x 4 colour blocks as its base-colour texture, a lamp panel
with an emissive texture, both 8-bit sRGB PNGs written here, and the same board
untextured (its peer: 16 squares, each of its block's decoded colour as its
baseColorFactor) for comparisons. tests/cli_gltf_texture.sh renders them.

usage: make_textured_gltf.py FOLDER
writes FOLDER/board.gltf (the board, z = 0, facing -z, (-1, -1) to (1, 1);
the lamp at z = 0.5 behind it, facing +z, away from the board and a camera
in front), board_base.png, lamp_emissive.png, board_peer.gltf and
blocks_lamp.gltf (a panel of the board's size and place, its winding
reversed to emit toward -z, whose
emissiveTexture is board_base.png, emissiveFactor EMISSIVE_FACTOR and
KHR_materials_emissive_strength EMISSIVE_STRENGTH); and two
boards with a metallicRoughnessTexture (glTF: roughness in green, metallic in
blue, linear): board_mr.gltf, the textured board whose 4 x 4 blocks are
metal and dielectric in a checkerboard (metallic 1 where row + column is
even), roughness 0.1 to 0.85 by block, and mr_furnace.gltf, a board of base
colour factor 0.8 grey with the same checkerboard, roughness 0 (smooth),
for the white furnace of tests/cli_gltf_metalrough.sh; both images are
board_mr.png and furnace_mr.png. board_uvx.gltf: the board_mr.gltf board whose
base colour and metallic-roughness maps are read through KHR_texture_transform
UVX (offset and scale), and board_uvx_peer.gltf, the same board without the
extension whose images (uvx_base.png, uvx_mr.png, 64 x 32) are board_base.png
and board_mr.png transformed on disk: each of their texel centres t the
source's texel centre at T R S t (glTF's order and its top-left origin), an
exact texel; board_uvr.gltf and board_uvr_peer.gltf (uvr_*.png) the same with
UVR (a quarter turn too) (tests/cli_gltf_uvx.sh). allmaps.gltf: the board with
every map glTF gives: base colour with an alpha channel (alphaMode MASK, one
block 0: a hole), board_mr.png's metallic-roughness, a normal map of four
tilted quadrants read through KHR_texture_transform (scale 2), an emissive
texture (one block glows) and an occlusion map (not rendered: warned)
(tests/cli_gltf_metalrough.sh renders it in every mode). ns_board.obj (with
ns_board.mtl): the board as an OBJ plane, Kd 0.5 grey, Ks 0.04, Ni 1.5, Ns
NS and map_Ns ns_exponent.png (4 x 4 grey blocks, t = (5 + 16 b) / 255 by
block b); ns_board.gltf, its glTF equivalent: base colour 0.5 grey,
metallic 0, roughness 1 and the map ns_rough.png, green the roughness
r = (2 / (NS t + 2))^(1/4) of Walter et al.'s alpha = r^2 = sqrt(2 / (NS t
+ 2)) for the exponent NS t (docs/SCENE_FORMAT.md; tests/cli_mtl_ns.sh).
The board's material: baseColorTexture x baseColorFactor (1 1 1), metallic 0,
roughness 0.5 (a coated material of alpha 0.25 in specmip); the lamp's:
emissiveTexture x emissiveFactor (1 1 1), base colour black."""
import base64, json, math, struct, sys, zlib

# the blocks' sRGB codes, row by row from the image's top left
CODES = [(200, 60, 50), (60, 160, 70), (50, 80, 190), (230, 210, 60),
         (128, 128, 128), (240, 240, 240), (20, 20, 20), (180, 90, 160),
         (90, 200, 200), (250, 140, 30), (100, 60, 30), (160, 200, 120),
         (30, 40, 90), (220, 170, 160), (70, 70, 160), (200, 30, 120)]
BLOCK = 8  # pixels a block
UVX = {"offset": [0.5, 0.25], "scale": [2, 1]}
UVR = {"offset": [0.5, 0.25], "rotation": math.pi / 2, "scale": [2, 1]}
EMISSIVE_FACTOR = [1.0, 0.8, 0.6]
EMISSIVE_STRENGTH = 2.5
NS = 200.0  # the MTL's Ns: the exponent map's scale


def srgb_decode(c):
    c /= 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def png(path, w, h, pixel):
    """An 8-bit RGB PNG of w x h, pixel(x, y) its sRGB codes (y from the top);
    RGBA when pixel gives four."""
    rgba = len(pixel(0, 0)) == 4
    raw = b"".join(b"\0" + bytes(v for x in range(w) for v in pixel(x, y)) for y in range(h))
    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data +
                struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6 if rgba else 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def gltf(path, quads, materials, images, extensions=None):
    """quads: (corners (4 x xyz, counter-clockwise seen from the front), uvs
    (4 x (u, v), v up) or None, material index); one mesh of one primitive per quad."""
    buf, views, accessors, meshes = b"", [], [], []
    def add(data, count, kind, ctype, extra=None):
        nonlocal buf
        views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(data)})
        buf += data + b"\0" * (-len(data) % 4)
        a = {"bufferView": len(views) - 1, "componentType": ctype, "count": count, "type": kind}
        a.update(extra or {})
        accessors.append(a)
        return len(accessors) - 1
    for corners, uvs, mat in quads:
        lo = [min(c[i] for c in corners) for i in range(3)]
        hi = [max(c[i] for c in corners) for i in range(3)]
        attrs = {"POSITION": add(b"".join(struct.pack("<3f", *c) for c in corners), 4, "VEC3",
                                 5126, {"min": lo, "max": hi})}
        if uvs:  # glTF's t runs down from the image's top: t = 1 - v
            attrs["TEXCOORD_0"] = add(b"".join(struct.pack("<2f", u, 1 - v) for u, v in uvs), 4,
                                      "VEC2", 5126)
        idx = add(struct.pack("<6H", 0, 1, 2, 0, 2, 3), 6, "SCALAR", 5123)
        meshes.append({"primitives": [{"attributes": attrs, "indices": idx, "material": mat}]})
    doc = {"asset": {"version": "2.0", "generator": "specmip tools/make_textured_gltf.py"},
           "scene": 0, "scenes": [{"nodes": list(range(len(meshes)))}],
           "nodes": [{"mesh": i} for i in range(len(meshes))], "meshes": meshes,
           "materials": materials,
           "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," +
                        base64.b64encode(buf).decode()}],
           "bufferViews": views, "accessors": accessors}
    if extensions:
        doc["extensionsUsed"] = extensions
    if images:
        doc["images"] = [{"uri": u} for u in images]
        doc["textures"] = [{"source": i} for i in range(len(images))]
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)


def main(folder):
    n = 4 * BLOCK
    png(folder + "/board_base.png", n, n,
        lambda x, y: CODES[(y // BLOCK) * 4 + x // BLOCK])
    # the lamp: a warm and a cool half, so its mean is neither
    png(folder + "/lamp_emissive.png", 16, 16,
        lambda x, y: (255, 180, 90) if x < 8 else (90, 160, 255))
    board = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]  # facing -z
    lamp = [(0.5, -0.5, 0.5), (-0.5, -0.5, 0.5), (-0.5, 0.5, 0.5), (0.5, 0.5, 0.5)]  # facing +z
    square = [(0, 0), (1, 0), (1, 1), (0, 1)]
    plastic = {"metallicFactor": 0.0, "roughnessFactor": 0.5}
    mats = [{"name": "board", "pbrMetallicRoughness": dict(plastic, baseColorTexture={"index": 0},
                                                           baseColorFactor=[1, 1, 1, 1])},
            {"name": "lamp", "pbrMetallicRoughness": dict(plastic, baseColorFactor=[0, 0, 0, 1]),
             "emissiveTexture": {"index": 1}, "emissiveFactor": [1, 1, 1]}]
    gltf(folder + "/board.gltf", [(board, square, 0), (lamp, square, 1)], mats,
         ["board_base.png", "lamp_emissive.png"])
    # the peer: block b (row r from the top, column c) covers x in
    # [-1 + c/2, -1 + (c+1)/2], y in [1 - (r+1)/2, 1 - r/2]
    quads, pmats = [], []
    for b, code in enumerate(CODES):
        r, c = b // 4, b % 4
        x0, x1, y0, y1 = -1 + c / 2, -1 + (c + 1) / 2, 1 - (r + 1) / 2, 1 - r / 2
        quads.append(([(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0)], None, b))
        pmats.append({"name": "block%d" % b, "pbrMetallicRoughness": dict(
            plastic, baseColorFactor=[srgb_decode(v) for v in code] + [1])})
    gltf(folder + "/board_peer.gltf", quads, pmats, [])
    lamp_mat = {"name": "blocks_lamp", "pbrMetallicRoughness": dict(plastic, baseColorFactor=[0, 0, 0, 1]),
                "emissiveTexture": {"index": 0}, "emissiveFactor": EMISSIVE_FACTOR,
                "extensions": {"KHR_materials_emissive_strength": {
                    "emissiveStrength": EMISSIVE_STRENGTH}}}
    front = [(1, -1, 0), (-1, -1, 0), (-1, 1, 0), (1, 1, 0)]  # the board's, wound to face -z
    gltf(folder + "/blocks_lamp.gltf", [(front, [(1, 0), (0, 0), (0, 1), (1, 1)], 0)], [lamp_mat],
         ["board_base.png"],
         ["KHR_materials_emissive_strength"])
    metal_roughness(folder, board, square)
    all_maps(folder, board, square)
    transformed(folder, board, "uvx", UVX)
    transformed(folder, board, "uvr", UVR)
    every_map(folder)
    ns_pair(folder, board, square)


def ns_pair(folder, board, square):
    """The MTL exponent map and its glTF roughness peer (the module's docstring)."""
    code = lambda x, y: 5 + 16 * ((y // BLOCK) * 4 + x // BLOCK)
    rough = lambda t: (2 / (NS * t + 2)) ** 0.25
    n = 4 * BLOCK
    png(folder + "/ns_exponent.png", n, n, lambda x, y: (code(x, y),) * 3)
    png(folder + "/ns_rough.png", n, n,
        lambda x, y: (0, round(255 * rough(code(x, y) / 255)), 0))
    with open(folder + "/ns_board.mtl", "w") as f:
        f.write("newmtl ns_board\nKd 0.5 0.5 0.5\nKs 0.04 0.04 0.04\nNi 1.5\nNs %g\n"
                "illum 2\nmap_Ns ns_exponent.png\n" % NS)
    with open(folder + "/ns_board.obj", "w") as f:
        f.write("mtllib ns_board.mtl\n" + "".join("v %g %g %g\n" % p for p in board) +
                "".join("vt %g %g\n" % t for t in square) +
                "usemtl ns_board\nf 1/1 2/2 3/3 4/4\n")
    mat = {"name": "ns_board", "pbrMetallicRoughness": {
        "baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0.0, "roughnessFactor": 1.0,
        "metallicRoughnessTexture": {"index": 0}}}
    gltf(folder + "/ns_board.gltf", [(board, square, 0)], [mat], ["ns_rough.png"])


def metal_roughness(folder, board, square):
    """The metallic checkerboard boards (the module's docstring)."""
    def mr(rough):  # metallic (blue) 255 on the blocks whose row + column is even
        return lambda x, y: (0, rough(y // BLOCK, x // BLOCK),
                             255 if (y // BLOCK + x // BLOCK) % 2 == 0 else 0)
    n = 4 * BLOCK
    png(folder + "/board_mr.png", n, n, mr(lambda r, c: 25 + 15 * (4 * r + c)))
    png(folder + "/furnace_mr.png", n, n, mr(lambda r, c: 0))
    textured = {"name": "board_mr", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1}}}
    gltf(folder + "/board_mr.gltf", [(board, square, 0)], [textured],
         ["board_base.png", "board_mr.png"])
    grey = {"name": "furnace_mr", "pbrMetallicRoughness": {
        "baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicRoughnessTexture": {"index": 0}}}
    gltf(folder + "/mr_furnace.gltf", [(board, square, 0)], [grey], ["furnace_mr.png"])


def all_maps(folder, board, square):
    """maps.gltf: the board with every map a glTF material may give beside
    the emissive one (blocks_lamp.gltf has that) — a base colour with alpha
    (board_rgba.png: the blocks, the right column's alpha 0, alphaMode MASK),
    board_mr.png as its metallic-roughness texture and a normal map of tilted
    stripes (board_nmap.png); tools/gltf_embed.py packs it as a GLB and with
    data: URIs for tests/cli_gltf_embedded.sh."""
    n = 4 * BLOCK
    png(folder + "/board_rgba.png", n, n,
        lambda x, y: CODES[(y // BLOCK) * 4 + x // BLOCK] + ((0,) if x >= 3 * BLOCK else (255,)))
    png(folder + "/board_nmap.png", n, n,
        lambda x, y: (200, 128, 230) if (x // 4) % 2 else (56, 128, 230))
    mats = [{"name": "maps_board", "alphaMode": "MASK", "alphaCutoff": 0.5,
             "normalTexture": {"index": 2, "scale": 1},
             "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                      "metallicRoughnessTexture": {"index": 1}}}]
    gltf(folder + "/maps.gltf", [(board, square, 0)], mats,
         ["board_rgba.png", "board_mr.png", "board_nmap.png"])


def on_disk(src, w, h, uvx, out_w, out_h):
    """pixel(x, y) of src (w x h) read at T R S of each texel centre of an
    out_w x out_h image (glTF's texture transform, uv from the top left)"""
    c, s = math.cos(uvx.get("rotation", 0)), math.sin(uvx.get("rotation", 0))
    (ox, oy), (sx, sy) = uvx["offset"], uvx["scale"]
    def pixel(x, y):
        u, v = (x + 0.5) / out_w, (y + 0.5) / out_h
        u2, v2 = c * sx * u + s * sy * v + ox, -s * sx * u + c * sy * v + oy
        i, j = u2 * w - 0.5, v2 * h - 0.5
        assert abs(i - round(i)) < 1e-6 and abs(j - round(j)) < 1e-6, "not a texel centre"
        return src(round(i) % w, round(j) % h)
    return pixel


def transformed(folder, board, name, uvx):
    """A transformed board and its peer (the module's docstring)."""
    n, square = 4 * BLOCK, [(0, 0), (1, 0), (1, 1), (0, 1)]
    base = lambda x, y: CODES[(y // BLOCK) * 4 + x // BLOCK]
    mr = lambda x, y: (0, 25 + 15 * (4 * (y // BLOCK) + x // BLOCK),
                       255 if (y // BLOCK + x // BLOCK) % 2 == 0 else 0)
    png(folder + "/%s_base.png" % name, 2 * n, n, on_disk(base, n, n, uvx, 2 * n, n))
    png(folder + "/%s_mr.png" % name, 2 * n, n, on_disk(mr, n, n, uvx, 2 * n, n))
    ext = {"extensions": {"KHR_texture_transform": uvx}}
    mat = {"name": "board_" + name, "pbrMetallicRoughness": {
        "baseColorTexture": dict({"index": 0}, **ext),
        "metallicRoughnessTexture": dict({"index": 1}, **ext)}}
    gltf(folder + "/board_%s.gltf" % name, [(board, square, 0)], [mat],
         ["board_base.png", "board_mr.png"], ["KHR_texture_transform"])
    peer = {"name": "board_" + name, "pbrMetallicRoughness": {
        "baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 1}}}
    gltf(folder + "/board_%s_peer.gltf" % name, [(board, square, 0)], [peer],
         ["%s_base.png" % name, "%s_mr.png" % name])

def every_map(folder):
    """The board with every map (the module's docstring), wound to face -z
    (the camera) as blocks_lamp.gltf, so that its emission is seen."""
    n, square = 4 * BLOCK, [(1, 0), (0, 0), (0, 1), (1, 1)]
    front = [(1, -1, 0), (-1, -1, 0), (-1, 1, 0), (1, 1, 0)]
    block = lambda x, y: (y // BLOCK) * 4 + x // BLOCK
    png(folder + "/all_base.png", n, n,
        lambda x, y: CODES[block(x, y)] + ((0 if block(x, y) == 5 else 255),))
    # tangent-space normals tilted 30 degrees to +-x and +-y by quadrant
    t = [(0.5, 0, 0.866), (-0.5, 0, 0.866), (0, 0.5, 0.866), (0, -0.5, 0.866)]
    png(folder + "/all_normal.png", 16, 16, lambda x, y: tuple(
        round(255 * (c + 1) / 2) for c in t[(y // 8) * 2 + x // 8]))
    png(folder + "/all_emissive.png", n, n,
        lambda x, y: (255, 200, 120) if block(x, y) == 10 else (0, 0, 0))
    png(folder + "/all_occlusion.png", n, n, lambda x, y: (128 + 4 * (x % 32),) * 3)
    mat = {"name": "allmaps", "alphaMode": "MASK", "alphaCutoff": 0.5,
           "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                    "metallicRoughnessTexture": {"index": 1}},
           "normalTexture": {"index": 2, "scale": 1.0, "extensions": {
               "KHR_texture_transform": {"scale": [2, 2]}}},
           "emissiveTexture": {"index": 3}, "emissiveFactor": [1, 1, 1],
           "occlusionTexture": {"index": 4}}
    gltf(folder + "/allmaps.gltf", [(front, square, 0)], [mat],
         ["all_base.png", "board_mr.png", "all_normal.png", "all_emissive.png",
          "all_occlusion.png"], ["KHR_texture_transform"])


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
