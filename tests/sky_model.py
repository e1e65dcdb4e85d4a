#!/usr/bin/env python3
"""The daylight sky and sun, evaluated here from the published model and
tables, independently of host/scene/sky.c, against what the renderer's
escaping rays met (tests/test_sky.c writes the dump).

Sky: Preetham, Shirley and Smits, "A Practical Analytic Model for Daylight"
(SIGGRAPH 1999), appendix A.2: the Perez distribution of Y, x and y with
coefficients linear in turbidity, the zenith luminance and chromaticity. Its
spectrum: the CIE daylight of that chromaticity (CIE 015:2018 eq. 4.7-4.9,
the basis spectra/cie_daylight_basis.csv), integrated here with the 1931
CMFs at 1 nm. Sun: ASTM G173's extraterrestrial irradiance through Rayleigh
and Angstrom aerosol transmittance along Kasten's relative air mass (the
paper's appendix A.1 after Iqbal 1983), over the disc's solid angle.

usage: sky_model.py ROOT DUMP
"""
import math
import sys

ROOT, DUMP = sys.argv[1], sys.argv[2]
HALF_DEG = 0.2665  # the sun's angular radius (half of 0.533 degrees)

# Tolerances, from the measured worst cases (printed below):
# luminance of a texel: the map stores float luminance; measured 6e-8 relative
Y_REL = 1e-5
# chromaticity of a texel's palette colour: the colour is the daylight
# spectrum of its (M1, M2) bin's mean, so its xy is off the direction's own
# by the bin's extent; measured worst 0.0017 (32 x 32 bins; 0.0046 with
# 12 x 12), bound 0.003
XY_ABS = 0.003
# the sun: its direction float; its luminance and xy integrated by the
# renderer over 1 nm bin means of the piecewise-linear spectrum, here by the
# trapezoid rule at the same samples: measured 2e-5 relative
SUN_REL = 1e-3
SUN_XY = 1e-4


def table(name):
    rows = []
    with open(f"{ROOT}/spectra/{name}") as f:
        lines = [l for l in f if not l.startswith("#")]
    for l in lines[1:]:
        rows.append([float(v) for v in l.strip().split(",")])
    return rows


def interp(rows, col, lam):
    for a, b in zip(rows, rows[1:]):
        if a[0] <= lam <= b[0]:
            f = (lam - a[0]) / (b[0] - a[0])
            return a[col] + f * (b[col] - a[col])
    raise ValueError(lam)


CMF = {int(r[0]): r[1:4] for r in table("cie1931_2deg_cmf_1nm.csv")}
LAMBDAS = range(380, 781)


def xyz_of(spec):
    """spec: a value per nm 380..780; trapezoid rule"""
    out = [0.0, 0.0, 0.0]
    for i, lam in enumerate(LAMBDAS):
        w = 0.5 if lam in (380, 780) else 1.0
        for c in range(3):
            out[c] += w * spec[i] * CMF[lam][c]
    return out


def chroma(xyz):
    s = sum(xyz)
    return xyz[0] / s, xyz[1] / s


def perez(coef, theta, gamma):
    A, B, C, D, E = coef
    first = 1.0 + A * math.exp(B / math.cos(theta)) if math.cos(theta) > 0 else 1.0
    return first * (1.0 + C * math.exp(D * gamma) + E * math.cos(gamma) ** 2)


def preetham(T, theta_s, theta, gamma):
    cY = [0.1787 * T - 1.4630, -0.3554 * T + 0.4275, -0.0227 * T + 5.3251,
          0.1206 * T - 2.5771, -0.0670 * T + 0.3703]
    cx = [-0.0193 * T - 0.2592, -0.0665 * T + 0.0008, -0.0004 * T + 0.2125,
          -0.0641 * T - 0.8989, -0.0033 * T + 0.0452]
    cy = [-0.0167 * T - 0.2608, -0.0950 * T + 0.0092, -0.0079 * T + 0.2102,
          -0.0441 * T - 1.6537, -0.0109 * T + 0.0529]
    chi = (4.0 / 9.0 - T / 120.0) * (math.pi - 2.0 * theta_s)
    Yz = (4.0453 * T - 4.9710) * math.tan(chi) - 0.2155 * T + 2.4192
    t1, t2, t3 = theta_s, theta_s ** 2, theta_s ** 3
    xz = (T * T * (0.00166 * t3 - 0.00375 * t2 + 0.00209 * t1)
          + T * (-0.02903 * t3 + 0.06377 * t2 - 0.03202 * t1 + 0.00394)
          + (0.11693 * t3 - 0.21196 * t2 + 0.06052 * t1 + 0.25886))
    yz = (T * T * (0.00275 * t3 - 0.00610 * t2 + 0.00317 * t1)
          + T * (-0.04214 * t3 + 0.08970 * t2 - 0.04153 * t1 + 0.00516)
          + (0.15346 * t3 - 0.26756 * t2 + 0.06670 * t1 + 0.26688))
    out = []
    for z, c in ((Yz, cY), (xz, cx), (yz, cy)):
        out.append(z * perez(c, theta, gamma) / perez(c, 0.0, theta_s))
    return out


BASIS = table("cie_daylight_basis.csv")


def daylight_xy(x, y):
    M = 0.0241 + 0.2562 * x - 0.7341 * y
    M1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / M
    M2 = (0.0300 - 31.4424 * x + 30.0717 * y) / M
    spec = [max(0.0, interp(BASIS, 1, l) + M1 * interp(BASIS, 2, l) + M2 * interp(BASIS, 3, l))
            for l in LAMBDAS]
    return chroma(xyz_of(spec))


def sun_dir(elev, azim):
    e, a = math.radians(elev), math.radians(azim)
    return [math.cos(e) * math.sin(a), math.sin(e), -math.cos(e) * math.cos(a)]


SOLAR = table("solar_astm_g173.csv")


def sun_radiance(elev, T):
    zen = 90.0 - elev
    m = 1.0 / (math.cos(math.radians(zen)) + 0.15 * (93.885 - zen) ** -1.253)
    beta = 0.04608365822050 * T - 0.04586025928522
    omega = 2.0 * math.pi * (1.0 - math.cos(math.radians(HALF_DEG)))
    L = []
    for lam in LAMBDAS:
        um = lam / 1000.0
        tau = math.exp(-0.008735 * m * um ** -4.08) * math.exp(-beta * m * um ** -1.3)
        L.append(interp(SOLAR, 1, lam) * tau / omega)
    return L


def main():
    fails = 0
    worst = {"Y": 0.0, "xy": 0.0, "basis": 0.0}
    sky = None
    for line in open(DUMP):
        f = line.split()
        if f[0] == "sky":
            elev, T, azim, w, h = float(f[1]), float(f[2]), float(f[3]), int(f[4]), int(f[5])
            ws = sun_dir(elev, azim)
            sky = (elev, T, azim)
            continue
        if f[0] == "texel":
            i, j = int(f[1]), int(f[2])
            Y, x, y = float(f[3]), float(f[4]), float(f[5])
            th, ph = math.pi * (j + 0.5) / h, 2 * math.pi * (i + 0.5) / w
            d = [math.sin(th) * math.sin(ph), math.cos(th), -math.sin(th) * math.cos(ph)]
            gamma = math.acos(max(-1.0, min(1.0, sum(a * b for a, b in zip(d, ws)))))
            mY, mx, my = preetham(T, math.radians(90 - elev), th, gamma)
            bx, by = daylight_xy(mx, my)
            eY = abs(Y - mY) / mY
            exy = max(abs(x - mx), abs(y - my))
            worst["Y"] = max(worst["Y"], eY)
            worst["xy"] = max(worst["xy"], exy)
            worst["basis"] = max(worst["basis"], abs(bx - mx), abs(by - my))
            if not (eY <= Y_REL and exy <= XY_ABS):
                fails += 1
                print(f"FAIL sky {sky} texel ({i}, {j}): Y {Y:.6g} x {x:.5f} y {y:.5f}, "
                      f"model Y {mY:.6g} x {mx:.5f} y {my:.5f}")
        if f[0] == "sun":
            elev, T, azim = sky
            w = [float(v) for v in f[1:4]]
            Y, x, y = float(f[4]), float(f[5]), float(f[6])
            L = sun_radiance(elev, T)
            xyz = xyz_of(L)
            mY = 683.0 * xyz[1] / 1000.0  # kcd/m^2
            mx, my = chroma(xyz)
            ed = max(abs(a - b) for a, b in zip(w, ws))
            eY = abs(Y - mY) / mY
            exy = max(abs(x - mx), abs(y - my))
            print(f"sun at {elev:g} deg, T {T:g}: {Y:.6g} kcd/m^2 x {x:.5f} y {y:.5f}; "
                  f"model {mY:.6g} x {mx:.5f} y {my:.5f}")
            if not (ed <= 1e-6 and eY <= SUN_REL and exy <= SUN_XY):
                fails += 1
                print(f"FAIL sun {sky}: direction off by {ed:.3g}, luminance {eY:.3g} relative, "
                      f"xy {exy:.3g}")
    print(f"texels: worst luminance {worst['Y']:.3g} relative, xy {worst['xy']:.4f} "
          f"(the daylight basis alone: {worst['basis']:.4f})")
    if sky is None:
        print("FAIL: the dump holds no sky")
        fails += 1
    sys.exit(1 if fails else 0)


main()
