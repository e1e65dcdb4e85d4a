#!/usr/bin/env python3
"""The twin of a scene whose textures are checkerboards, each texture replaced by its mean
colour (docs/METHODS.md "Textures", speed): every `reflect texture NAME` becomes
`reflect NAME_mean`, a spectrum written inline, the checker's mean linear sRGB (the squares'
mean, as the scene reader computes it) lifted by the Jakob-Hanika model, its three
coefficients fitted here by Gauss-Newton on CIELAB under D65 (CIE 1931 2 degree observer,
1 nm, colour-science's data), as host/scene/rgb2spec.c fits one colour; written at 5 nm.
Prints the twin on stdout.

usage: PY bench/texture_mean_scene.py SCENE > TWIN.scene (PY with colour-science: build/pyenv)
"""
import math
import re
import sys
import warnings

warnings.filterwarnings("ignore")
import colour  # noqa: E402
import numpy as np  # noqa: E402

LAM = np.arange(380, 781)
CMF = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(
    colour.SpectralShape(380, 780, 1)).values
D65 = colour.SDS_ILLUMINANTS["D65"].copy().align(colour.SpectralShape(380, 780, 1)).values
WHITE = (CMF * D65[:, None]).sum(0)
X = (LAM - 380.0) / 400.0


def sigmoid_sd(c):
    z = (c[0] * X + c[1]) * X + c[2]
    return 0.5 + 0.5 * z / np.sqrt(1.0 + z * z)


def lab(sd):
    xyz = (CMF * (D65 * sd)[:, None]).sum(0) / WHITE[1]
    return colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(WHITE / WHITE[1]))


def lift(rgb):
    """Gauss-Newton with a numeric Jacobian from grey: the coefficients whose spectrum under
    D65 has the colour's CIELAB."""
    want = colour.XYZ_to_Lab(colour.RGB_to_XYZ(rgb, colour.RGB_COLOURSPACES["sRGB"],
                                               apply_cctf_decoding=False),
                             colour.XYZ_to_xy(WHITE / WHITE[1]))
    c = np.zeros(3)
    for _ in range(60):
        r = lab(sigmoid_sd(c)) - want
        J = np.stack([(lab(sigmoid_sd(c + d)) - lab(sigmoid_sd(c - d))) / 2e-4
                      for d in np.eye(3) * 1e-4], 1)
        c = c - np.linalg.lstsq(J, r, rcond=None)[0]
    return sigmoid_sd(c), float(np.abs(lab(sigmoid_sd(c)) - want).max())

src = open(sys.argv[1]).read()
means = {}
for m in re.finditer(r"^texture\s+(\S+)\s+checker\s+(\d+)\s+((?:\S+\s+){5}\S+)", src, re.M):
    n = int(m.group(2)) ** 2
    c = [float(v) for v in m.group(3).split()]
    na = math.ceil(n / 2)
    means[m.group(1)] = [(na * c[k] + (n - na) * c[3 + k]) / n for k in range(3)]
out = []
for line in src.splitlines():
    if re.match(r"^texture\s", line):
        continue
    for name in means:
        line = re.sub(r"reflect\s+texture\s+%s\b" % re.escape(name), "reflect %s_mean" % name, line)
    if re.match(r"^material\s", line) and not any(l.startswith("spectrum ") and "_mean" in l for l in out):
        for name, rgb in means.items():
            sd, err = lift(rgb)
            pairs = " ".join("%d %.5f" % (w, v) for w, v in zip(LAM[::5], sd[::5]))
            out.append("# %s's mean, linear sRGB %.4f %.4f %.4f (fit within CIELAB %.1g)" %
                       (name, *rgb, err))
            out.append("spectrum %s_mean inline %s end" % (name, pairs))
    out.append(line)
print("\n".join(out))
