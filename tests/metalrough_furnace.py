"""The metallic checkerboard of tools/make_textured_gltf.py (mr_furnace.gltf: base
colour 0.8 grey, metallic 1 on the blocks whose row + column is even, 0 on the
others, roughness 0) in a white furnace seen head-on (tests/cli_gltf_metalrough.sh):
per block, the middle half of its pixels' mean linear sRGB against its closed form,
  metal:  F(1) = F0 = R (the Gulbrandsen conductor reflects R at normal incidence),
  coated: Fo + (1 - Fo) R (1 - Fdr_e) / (eta^2 (1 - Fdr_i R)), Fo = ((eta - 1) /
          (eta + 1))^2, Fdr_e and Fdr_i the dielectric's diffuse reflectances from
          outside and inside (integrals of F(mu) 2 mu over mu in [0, 1], here by
          Gauss-Legendre quadrature of the exact Fresnel; Mitsuba's plastic),
within CIEDE2000 LIMIT. usage: metalrough_furnace.py IMAGE.exr LIMIT [R ETA];
exit 1 when a block is off, printing it, then the worst."""
import sys, warnings
warnings.filterwarnings("ignore")
import numpy as np, colour, OpenImageIO as oiio


def fresnel(eta, c):
    """unpolarised Fresnel reflectance of a dielectric of relative index eta at cosine c"""
    s2 = (1.0 - c * c) / (eta * eta)
    if s2 >= 1.0:
        return 1.0
    ct = np.sqrt(1.0 - s2)
    rs = (c - eta * ct) / (c + eta * ct)
    rp = (eta * c - ct) / (eta * c + ct)
    return 0.5 * (rs * rs + rp * rp)


def fdr(eta):
    x, w = np.polynomial.legendre.leggauss(400)
    mu = 0.5 * (x + 1.0)  # on [0, 1]
    return float(sum(0.5 * wi * fresnel(eta, m) * 2.0 * m for m, wi in zip(mu, w)))


def closed_forms(r, eta):
    fo = ((eta - 1.0) / (eta + 1.0)) ** 2
    fe, fi = fdr(eta), fdr(1.0 / eta)
    return r, fo + (1.0 - fo) * r * (1.0 - fe) / (eta * eta * (1.0 - fi * r))


def main():
    limit = float(sys.argv[2])
    r = float(sys.argv[3]) if len(sys.argv) > 3 else 0.8
    eta = float(sys.argv[4]) if len(sys.argv) > 4 else 1.5
    metal, coated = closed_forms(r, eta)
    img = oiio.ImageBuf(sys.argv[1]).get_pixels(oiio.FLOAT)[..., :3]
    n = img.shape[0] // 4
    white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    def lab(rgb):
        return colour.XYZ_to_Lab(colour.sRGB_to_XYZ(rgb, apply_cctf_decoding=False), white)
    worst = {"metal": 0.0, "coated": 0.0}
    for b in range(16):
        row, col = b // 4, b % 4
        kind = "metal" if (row + col) % 2 == 0 else "coated"
        want = np.full(3, metal if kind == "metal" else coated)
        got = img[n * row + n // 4:n * row + 3 * n // 4,
                  n * col + n // 4:n * col + 3 * n // 4].reshape(-1, 3).mean(axis=0)
        de = float(colour.delta_E(lab(want), lab(got), method="CIE 2000"))
        worst[kind] = max(worst[kind], de)
        if de > limit:
            print("block %d (%s): closed form %.4f, image %s: dE00 %.2f" % (b, kind, want[0], got, de))
    print("closed forms: metal %.4f, coated %.4f; worst dE00 metal %.3f, coated %.3f" %
          (metal, coated, worst["metal"], worst["coated"]))
    sys.exit(max(worst.values()) > limit)


main()
