#!/usr/bin/env python3
"""specmip's environment map against Mitsuba 3's `envmap` (docs/VALIDATION_MITSUBA.md,
"Environment maps"): one Mitsuba XML read by both, a diffuse sphere on a diffuse floor under
a map written here (256 x 128: a sky graded along u and v and a soft sun, 6 degrees wide,
60 times the sky; smooth, since Mitsuba interpolates texels bilinearly and specmip takes the
nearest), scale 1.5, turned 30 degrees about +y. Mitsuba (scalar_spectral) renders it with
seeds 1 and 2, specmip in truth; printed: each image's mean linear sRGB, and `specmip compare`'s
mean dE00 of specmip against Mitsuba seed 1 and of seed 2 against seed 1 (the floor).

usage: VENV/bin/python bench/peers/mitsuba_envmap.py [--spp N] [--specmip build/specmip] [--out DIR]
"""
import argparse
import math
import os
import subprocess
import sys

import mitsuba as mi

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from gen_envmap import direction, rgbe  # noqa: E402 (the bundled map's writer)

XML = """<scene version="3.0.0">
  <integrator type="path"/>
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 1.1, -5" target="0, 0.5, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><rfilter type="box"/><integer name="width" value="96"/><integer name="height" value="64"/></film>
    <sampler type="independent"><integer name="sample_count" value="{spp}"/></sampler>
  </sensor>
  <emitter type="envmap">
    <string name="filename" value="sky.hdr"/>
    <float name="scale" value="1.5"/>
    <transform name="to_world"><rotate y="1" angle="30"/></transform>
  </emitter>
  <bsdf type="diffuse" id="w"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf>
  <shape type="sphere"><point name="center" x="0" y="0.6" z="0"/><float name="radius" value="0.6"/><ref id="w"/></shape>
  <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="-90"/><scale value="10"/></transform><ref id="w"/></shape>
</scene>
"""


def write_map(path, w=256, h=128):
    sun = direction(0.3, 0.3)
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
        for j in range(h):
            for i in range(w):
                u, v = (i + 0.5) / w, (j + 0.5) / h
                c = sum(a * b for a, b in zip(direction(u, v), sun))
                s = 60 * math.exp(-(math.acos(max(-1, min(1, c))) / math.radians(6)) ** 2)
                f.write(rgbe((0.3 + 0.3 * v + 0.2 * u + s, 0.4 + 0.2 * v + 0.85 * s,
                              0.8 - 0.4 * v + 0.6 * s)))


def mean_rgb(exr):
    r = subprocess.run(["oiiotool", exr, "--printstats"], capture_output=True, text=True)
    avg = [line.split(":")[1].split()[:3] for line in r.stdout.splitlines() if "Stats Avg" in line]
    if not avg:
        raise SystemExit(f"oiiotool could not read {exr}: {r.stderr.strip()}")
    return avg[0]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--specmip", default="build/specmip")
    ap.add_argument("--out", default="mitsuba_envmap")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    write_map(os.path.join(a.out, "sky.hdr"))
    xml = os.path.join(a.out, "scene.xml")
    open(xml, "w").write(XML.format(spp=a.spp))
    mi.set_variant("scalar_spectral")
    scene = mi.load_file(xml)
    for seed in (1, 2):
        mi.util.write_bitmap(os.path.join(a.out, f"mitsuba{seed}.exr"), mi.render(scene, seed=seed),
                            write_async=False)
    sp = os.path.join(a.out, "specmip.exr")
    subprocess.run([a.specmip, "render", xml, "--mode", "truth", "--quiet", "-o", sp], check=True)
    for name in ("specmip", "mitsuba1", "mitsuba2"):
        print(name, "mean linear sRGB", *mean_rgb(os.path.join(a.out, name + ".exr")))
    for a_, b_ in (("mitsuba1", "specmip"), ("mitsuba1", "mitsuba2")):
        r = subprocess.run([a.specmip, "compare", os.path.join(a.out, a_ + ".exr"),
                            os.path.join(a.out, b_ + ".exr")], capture_output=True, text=True)
        mean = [l for l in r.stdout.splitlines() if l.startswith("dE00")][0].split()[1]
        print(f"{b_} against {a_}: mean dE00 {mean}")


if __name__ == "__main__":
    main()
