#!/usr/bin/env python3
"""specmip's image textures against Mitsuba 3's `bitmap` (docs/VALIDATION_MITSUBA.md,
"Textures"): a floor and a back wall, two Lambertian quads textured with 8-bit sRGB PNGs
written here (64 x 64 texels, larger than a pixel where they are seen, so both renderers
read level 0 of the image), facing each other at a right angle so each is lit by the other's
texture too, under a uniform sky of luminance 1 (Mitsuba `constant` radiance RGB 1, specmip
`background both` D65 at luminance 1). The same geometry is written twice: an OBJ pair with
texture coordinates and an XML for Mitsuba, a .scene for specmip. Mitsuba (scalar_spectral,
its bitmap bilinear, its RGB upsampled by its own Jakob-Hanika table) renders with seeds 1
and 2, specmip in truth (stochastic trilinear filtering by ray cones, texels lifted on its
16^3 colour grid); printed: each image's mean linear sRGB and `specmip compare`'s mean dE00
of specmip against Mitsuba seed 1 and of seed 2 against seed 1 (the floor).

usage: VENV/bin/python bench/peers/mitsuba_texture.py [--spp N] [--specmip build/specmip] [--out DIR]
"""
import argparse
import os
import subprocess

import mitsuba as mi
import numpy as np

from mitsuba_envmap import mean_rgb  # noqa: E402 (this folder's peer: oiiotool's means)

W, H = 96, 64
# the floor y = 0 and the back wall z = 1, their corners in the order u, v = (0 0) (1 0) (1 1) (0 1)
FLOOR = [(-2, 0, -2), (2, 0, -2), (2, 0, 1), (-2, 0, 1)]
WALL = [(-2, 0, 1), (2, 0, 1), (2, 2.5, 1), (-2, 2.5, 1)]
UV = [(0, 0), (1, 0), (1, 1), (0, 1)]

XML = """<scene version="3.0.0">
  <integrator type="path"/>
  <sensor type="perspective">
    <float name="fov" value="50"/>
    <transform name="to_world"><lookat origin="0, 2.8, -3.4" target="0, 0.5, 0.4" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><rfilter type="box"/><integer name="width" value="{w}"/><integer name="height" value="{h}"/></film>
    <sampler type="independent"><integer name="sample_count" value="{spp}"/></sampler>
  </sensor>
  <emitter type="constant"><rgb name="radiance" value="1, 1, 1"/></emitter>
  <shape type="obj"><string name="filename" value="floor.obj"/>
    <bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="floor.png"/></texture></bsdf></shape>
  <shape type="obj"><string name="filename" value="wall.obj"/>
    <bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="wall.png"/></texture></bsdf></shape>
</scene>
"""

SCENE = """image {w} {h}
spp {spp}
camera position 0 2.8 -3.4  lookat 0 0.5 0.4  fov 50
spectrum d65 file illuminant_D65.csv
texture floor floor.png
texture wall wall.png
material floor reflect texture floor
material wall reflect texture wall
quad floor {floor} uv {uv}
quad wall {wall} uv {uv}
background both d65 1
"""


def texture(kind, n=64):
    """8-bit sRGB codes: the floor 8 x 8 tiles of a hue ramp, the wall stripes and a
    saturated diagonal gradient (both asymmetric, so a flip shows)."""
    y, x = np.mgrid[0:n, 0:n] / (n - 1.0)
    if kind == "floor":
        t = (np.floor(x * 7.999) + 8 * np.floor(y * 7.999)) / 63.0
        rgb = np.stack([0.15 + 0.8 * t, 0.9 - 0.7 * t, 0.2 + 0.6 * (np.floor(x * 7.999) % 2)], -1)
    else:
        rgb = np.stack([0.9 * x, 0.1 + 0.3 * (np.floor(y * 12) % 2), 0.9 * (1 - x) * (1 - y) + 0.05], -1)
    return np.round(np.clip(rgb, 0, 1) * 255).astype(np.uint8)


def write_obj(path, corners):
    with open(path, "w") as f:
        for p in corners:
            f.write("v %g %g %g\n" % p)
        for t in UV:
            f.write("vt %g %g\n" % t)
        # wound so that the normal faces the camera: Mitsuba's diffuse is one-sided
        f.write("f 1/1 3/3 2/2\nf 1/1 4/4 3/3\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--specmip", default="build/specmip")
    ap.add_argument("--out", default="mitsuba_texture")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    mi.set_variant("scalar_spectral")
    for kind in ("floor", "wall"):
        mi.Bitmap(texture(kind), mi.Bitmap.PixelFormat.RGB).write(os.path.join(a.out, kind + ".png"))
    write_obj(os.path.join(a.out, "floor.obj"), FLOOR)
    write_obj(os.path.join(a.out, "wall.obj"), WALL)
    xml, sc = os.path.join(a.out, "scene.xml"), os.path.join(a.out, "scene.scene")
    open(xml, "w").write(XML.format(w=W, h=H, spp=a.spp))
    # Mitsuba's camera puts world +x on the image's left where specmip's puts it on the
    # right (mitsuba_sensor.c): specmip's copy is mirrored in x, its textures with it
    flat = lambda q: "  ".join("%g %g %g" % (-p[0], p[1], p[2]) for p in q)  # noqa: E731
    open(sc, "w").write(SCENE.format(w=W, h=H, spp=a.spp, floor=flat(FLOOR), wall=flat(WALL),
                                     uv="  ".join("%g %g" % t for t in UV)))
    scene = mi.load_file(xml)
    for seed in (1, 2):
        mi.util.write_bitmap(os.path.join(a.out, f"mitsuba{seed}.exr"), mi.render(scene, seed=seed),
                             write_async=False)
    sp = os.path.join(a.out, "specmip.exr")
    subprocess.run([a.specmip, "render", sc, "--mode", "truth", "--quiet", "-o", sp], check=True)
    exr = {n: os.path.join(a.out, n + ".exr") for n in ("specmip", "mitsuba1", "mitsuba2")}
    print("\n".join("%s mean linear sRGB %s" % (n, " ".join(mean_rgb(f))) for n, f in exr.items()))
    for other in ("specmip", "mitsuba2"):
        out = subprocess.run([a.specmip, "compare", exr["mitsuba1"], exr[other]],
                             capture_output=True, text=True).stdout.splitlines()
        print(other, "against mitsuba1: mean dE00", next(l for l in out if l.startswith("dE00")).split()[1])


if __name__ == "__main__":
    main()
