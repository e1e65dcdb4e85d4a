#!/usr/bin/env python3
"""Writes the bundled environment map scenes/sunsky.hdr (used by
scenes/envmap.scene): a 128 x 64 equirectangular Radiance HDR (RGBE,
uncompressed scanlines, linear sRGB), made of formulas so that it carries no
data of unknown origin:

  sky     above the horizon: blue at the zenith to a pale haze at the horizon
  sun     a disc of 3 degrees radius at elevation 35 degrees, 4000 times the
          zenith's radiance, warm white
  ground  below the horizon: a flat brown-grey

The convention is the renderer's (docs/SCENE_FORMAT.md, `background map`): row
0 looks up, u = atan2(x, -z) / 2 pi. The output is the same bytes on every run.

usage: tools/gen_envmap.py [OUT]   (default: scenes/sunsky.hdr beside this tool)
"""
import math
import os
import sys

W, H = 128, 64
SUN_ELEV, SUN_AZ, SUN_RADIUS = math.radians(35.0), 0.62, math.radians(3.0)


def rgbe(c):
    m = max(c)
    if m < 1e-32:
        return bytes(4)
    mant, e = math.frexp(m)
    f = math.ldexp(1.0, -e) * 256.0
    return bytes([int(c[0] * f), int(c[1] * f), int(c[2] * f), e + 128])


def direction(u, v):
    th, ph = math.pi * v, 2.0 * math.pi * u
    return (math.sin(th) * math.sin(ph), math.cos(th), -math.sin(th) * math.cos(ph))


def texel(i, j):
    u, v = (i + 0.5) / W, (j + 0.5) / H
    d = direction(u, v)
    s = direction(SUN_AZ, 0.5 - SUN_ELEV / math.pi)
    cosang = sum(a * b for a, b in zip(d, s))
    if cosang > math.cos(SUN_RADIUS):
        return (4000.0 * 1.0, 4000.0 * 0.92, 4000.0 * 0.80)
    if d[1] < 0.0:
        return (0.16, 0.14, 0.12)
    t = 1.0 - d[1]  # 0 at the zenith, 1 at the horizon
    zen, hor = (0.20, 0.35, 0.75), (0.75, 0.80, 0.85)
    return tuple(z + (h - z) * t ** 3 for z, h in zip(zen, hor))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "scenes", "sunsky.hdr")
    with open(out, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (H, W))
        for j in range(H):
            f.write(b"".join(rgbe(texel(i, j)) for i in range(W)))


if __name__ == "__main__":
    main()
