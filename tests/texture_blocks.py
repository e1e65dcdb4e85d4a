"""A textured quad's image against its 4 x 4 blocks texture (tests/cli_texture_quad.sh,
tests/cli_mesh_texture.sh): per block, the middle half of its pixels' mean linear sRGB
within CIEDE2000 1 of the decoded texel. usage: texture_blocks.py write TEXTURE.png (an 8-bit sRGB PNG of 32 x 32 pixels, 4 x 4
blocks of 16 colours), or texture_blocks.py TEXTURE.png IMAGE.exr [FACTOR] (the image
divided by FACTOR first, one number or R,G,B: an emission's factor), or
texture_blocks.py pair PEER.exr IMAGE.exr LIMIT (each block against the same block of
a peer image of the same size, within CIEDE2000 LIMIT);
exit 1 when a block is off, printing it, then the worst."""
import sys
if sys.argv[1] == "write":
    import numpy as np, OpenImageIO as oiio
    codes = [(200, 60, 50), (60, 160, 70), (50, 80, 190), (230, 210, 60),
             (128, 128, 128), (240, 240, 240), (20, 20, 20), (180, 90, 160),
             (90, 200, 200), (250, 140, 30), (100, 60, 30), (160, 200, 120),
             (30, 40, 90), (220, 170, 160), (70, 70, 160), (200, 30, 120)]
    img = np.zeros((32, 32, 3), np.uint8)
    for b, c in enumerate(codes):
        img[8 * (b // 4):8 * (b // 4) + 8, 8 * (b % 4):8 * (b % 4) + 8] = c
    spec = oiio.ImageSpec(32, 32, 3, "uint8")
    spec.attribute("oiio:ColorSpace", "sRGB")
    out = oiio.ImageOutput.create(sys.argv[2])
    assert out.open(sys.argv[2], spec) and out.write_image(img) and out.close()
    sys.exit(0)

import sys, warnings
warnings.filterwarnings("ignore")
import numpy as np, colour, OpenImageIO as oiio
limit = 1.0
if sys.argv[1] == "pair":  # a peer image's blocks in place of the texels
    limit = float(sys.argv[4])
    peer = oiio.ImageBuf(sys.argv[2]).get_pixels(oiio.FLOAT)[..., :3]
    lin = np.zeros((32, 32, 3))
    for b in range(16):
        r, c = b // 4, b % 4
        lin[8 * r + 4, 8 * c + 4] = peer[8 * r + 2:8 * r + 6, 8 * c + 2:8 * c + 6].reshape(-1, 3).mean(axis=0)
    img = oiio.ImageBuf(sys.argv[3]).get_pixels(oiio.FLOAT)[..., :3]
else:
    tex = oiio.ImageBuf(sys.argv[1]).get_pixels(oiio.UINT8)[..., :3] / 255.0
    img = oiio.ImageBuf(sys.argv[2]).get_pixels(oiio.FLOAT)[..., :3]
    if len(sys.argv) > 3:  # one factor, or one per channel: "R,G,B"
        img = img / np.array([float(f) for f in sys.argv[3].split(",")])
    lin = colour.models.eotf_sRGB(tex)
if img.shape[0] < 32 or img.shape[1] < 32:
    print("the image is %s, not 32 x 32" % (img.shape,))
    sys.exit(1)
white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
def lab(rgb):
    return colour.XYZ_to_Lab(colour.sRGB_to_XYZ(rgb, apply_cctf_decoding=False), white)
worst = 0.0
for b in range(16):
    r, c = b // 4, b % 4
    want = lin[8 * r + 4, 8 * c + 4]
    got = img[8 * r + 2:8 * r + 6, 8 * c + 2:8 * c + 6].reshape(-1, 3).mean(axis=0)
    de = float(colour.delta_E(lab(want), lab(got), method="CIE 2000"))
    worst = max(worst, de)
    if de > limit:
        print("block %d: texel %s, image %s: dE00 %.2f" % (b, want, got, de))
print("worst %.3f" % worst)
sys.exit(worst > limit)
