#!/usr/bin/env python3
"""Renders a specmip scene with Mitsuba 3 (scalar_spectral) and compares it with specmip.

The scene (docs/SCENE_FORMAT.md) is converted, not approximated:
  - geometry: `tri` and `quad` as written, `mesh` files (PLY or OBJ, `material` and
    `smooth`/`flat` clauses) with their transform clauses composed in the order written;
    flat-shaded (Mitsuba's face_normals) where specmip shades flat, front faces as specmip's
    (b - a) x (c - a); a mesh file with vertex normals whose material is a conductor,
    dielectric or coated one (or any under `smooth`, not under `flat`) shades smooth in
    specmip (docs/SCENE_FORMAT.md), and in Mitsuba with the file's vertex normals (its
    default, face_normals false). Mitsuba's shading-normal rule is its own (no bend, no
    rejection; its dielectric takes inside from the shading normal's side), so the two
    differ where a shading normal leans far from its facet: a coarse mesh's silhouette;
  - Lambertian materials: `twosided` `diffuse` with the spectral reflectance (specmip's
    surfaces reflect on both faces), the data's samples inside 380-780 nm, extended by the end
    values as specmip extends a reflectance;
  - emitters: `area` lights (one-sided, as specmip's) whose radiance is specmip's normalised
    emission: the spectrum times SCALE / Y, Y = sum(S ybar) / sum(ybar) over specmip's 1 nm bins
    of 380-780 nm (host/scene/scene.c spm_sb_emission, host/colour/spectrum.c), zero outside
    380-780 nm (Mitsuba integrates 360-830), and multiplied by 106.856895 / the integral of ybar
    over 380-780 nm, since Mitsuba divides the XYZ integral by the full ybar integral (its
    CIE_Y_INTEGRAL) where specmip divides by the 380-780 one; the two differ by 4e-6;
  - conductors (`material NAME conductor ETA K [alpha A]`): `twosided` `conductor` (no alpha)
    or `roughconductor` (distribution ggx, sample_visible, the same alpha), spectral eta and k
    extended by their end values;
  - coated materials (`material NAME coated reflect R [S] ior N [alpha A]`): `twosided`
    `plastic` (no alpha) or `roughplastic` (distribution ggx, sample_visible, the same alpha),
    int_ior N, ext_ior 1 (Mitsuba's default is air's 1.000277), nonlinear true, the spectral
    diffuse_reflectance (coated_material, coated_bsdf below). Mitsuba's plastic takes its
    internal diffuse reflectance from a polynomial fit and its roughplastic the rough lobe's
    tabulated albedo for the diffuse lobe's transmission, where specmip integrates the smooth
    Fresnel (docs/METHODS.md "Coatings"): small differences by design;
  - `light point|spot|distant` statements: Mitsuba's `point`, `spot` (its falloff linear in
    the angle, specmip's default shape; other shapes are an error) and `directional`
    emitters, the intensity or irradiance per unit of the spectrum converted as an area
    light's radiance is, a POWER divided by 4 pi or the spot's falloff's solid angle;
  - the camera: `perspective`, the horizontal field of view (fov_axis x), up +y, box pixel
    filter, `independent` sampler; the `path` integrator without a depth limit (with
    --integrator light: `ptracer`, against specmip's --integrator light).
Unsupported (an error, exit 2): `twosided` emitters, `background`, MiniLight files, mesh
formats other than PLY/OBJ, `bind`.

Then it renders Mitsuba with two seeds and specmip `truth` (build/specmip render --mode truth),
and compares the linear images with `specmip compare` (CIEDE2000 after its default 5x5 box blur,
one white for both comparisons: the 99.9th percentile of the first Mitsuba image's Y):
  mean dE00 of specmip against Mitsuba seed 1, the floor (mean dE00 of Mitsuba seed 2 against
  seed 1), their ratio, and the ratio of mean luminance specmip / Mitsuba (both seeds averaged).
Agreement, as docs state it: mean dE00 <= 1.5 x floor and luminance within 1 %. Exit status:
0 when every scene agrees, 1 when one does not (at a few spp noise alone can do that), 2 for a
scene it cannot convert. Figures at 512 spp: README "Against Mitsuba 3".

Running it (Mitsuba is a large download, so tools/test.sh does not run this):
  python3 -m venv /work/venv-mitsuba && /work/venv-mitsuba/bin/pip install mitsuba==3.9.1 numpy
  /work/venv-mitsuba/bin/python bench/peers/mitsuba_compare.py scenes/cornell.scene \\
      [more scenes] [--spp 256] [--width 128] [--specmip build/specmip] [--out DIR] [--md]
  /work/venv-mitsuba/bin/python bench/peers/mitsuba_compare.py --check-ior
      (checks spectra/metal_*.csv against the wheel's mitsuba/data/ior files)
  ... --convert-only SCENE --out DIR   (writes the Mitsuba scene as PLY files + scene.json)
  ... --mitsuba-only SCENE...          (Mitsuba alone, seed 1: for scenes specmip cannot read)
"""
import argparse
import glob
import json
import math
import os
import shlex
import struct
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, '..', '..'))
LMIN, LMAX = 380.0, 780.0
SMOOTH_ALPHA = 1e-3  # a conductor's alpha below this renders smooth in specmip (SPM_COND_MIN_ALPHA)
CIE_Y_INTEGRAL_MITSUBA = 106.856895  # Mitsuba 3's CIE_Y_INTEGRAL (the 360-830 nm integral)


class SceneError(Exception):
    pass


# ---------------------------------------------------------------- spectra

def read_csv(path, column=None):
    """(wavelengths, values) of a spectra CSV: '#' comments, a header, numeric rows."""
    rows, header = [], None
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith('#'):
                continue
            cells = [c.strip() for c in line.split(',')]
            if header is None:
                header = cells
                continue
            rows.append([float(c) for c in cells])
    if header is None or not rows:
        raise SceneError('%s: no data' % path)
    if column is None:
        if len(header) != 2:
            raise SceneError('%s: several value columns, a column is needed' % path)
        col = 1
    else:
        if column not in header:
            raise SceneError('%s: no column %s' % (path, column))
        col = header.index(column)
    return [r[0] for r in rows], [r[col] for r in rows]


def lerp_at(wl, v, x):
    """Piecewise-linear value at x, the end values beyond the data."""
    if x <= wl[0]:
        return v[0]
    if x >= wl[-1]:
        return v[-1]
    lo, hi = 0, len(wl) - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if wl[mid] <= x:
            lo = mid
        else:
            hi = mid
    t = (x - wl[lo]) / (wl[hi] - wl[lo])
    return v[lo] + t * (v[hi] - v[lo])


def clip_range(wl, v):
    """The samples inside 380-780 nm plus the values at 380 and 780 (end values beyond the
    data): the piecewise-linear function specmip integrates, restricted to its range."""
    pts = [(LMIN, lerp_at(wl, v, LMIN))]
    pts += [(a, b) for a, b in zip(wl, v) if LMIN < a < LMAX]
    pts.append((LMAX, lerp_at(wl, v, LMAX)))
    return [p[0] for p in pts], [p[1] for p in pts]


def bin_means(wl, v):
    """Means over specmip's 400 bins of 1 nm of the piecewise-linear function (exact for
    piecewise-linear data: integrate each linear piece)."""
    out = []
    for i in range(400):
        a, b = LMIN + i, LMIN + i + 1
        xs = [a] + [x for x in wl if a < x < b] + [b]
        s = 0.0
        for x0, x1 in zip(xs, xs[1:]):
            s += 0.5 * (lerp_at(wl, v, x0) + lerp_at(wl, v, x1)) * (x1 - x0)
        out.append(s)
    return out


_CMF = None


def cmf_y_bins():
    global _CMF
    if _CMF is None:
        wl, y = read_csv(os.path.join(ROOT, 'spectra', 'cie1931_2deg_cmf_1nm.csv'), 'y')
        _CMF = bin_means(wl, y)
    return _CMF


def planck(lam_nm, kelvin):
    c1, c2 = 3.74183e-16, 1.4388e-2
    lam = lam_nm * 1e-9
    return c1 / (lam ** 5 * (math.exp(c2 / (lam * kelvin)) - 1.0))


class Spectrum:
    def __init__(self, wl, v, kind):
        self.wl, self.v, self.kind = wl, v, kind  # kind: data | equal | blackbody


def find_spectrum_file(name, scene_dir):
    for p in (name, os.path.join(scene_dir, name), os.path.join(ROOT, 'spectra', name)):
        if os.path.isfile(p):
            return p
    raise SceneError('spectrum file %s not found' % name)


# ---------------------------------------------------------------- scene parser

def tokenize(path):
    """[(line number, [tokens])] with comments dropped and quoted names kept whole."""
    out = []
    with open(path) as f:
        for n, line in enumerate(f, 1):
            lex = shlex.shlex(line.replace('\r', ''), posix=True)
            lex.whitespace_split = True
            lex.commenters = '#'
            toks = list(lex)
            if toks:
                out.append((n, toks))
    return out


class Scene:
    def __init__(self):
        self.width = self.height = None
        self.spp = None
        self.camera = None  # (pos, dir, fov)
        self.spectra = {}
        self.materials = {}  # name -> dict
        self.tris = []  # (material, (p0, p1, p2))
        self.meshes = []  # (path, material, 4x4 matrix rows)
        self.lights = []  # (kind, dict of its values)


def num(t, where):
    try:
        x = float(t)
    except ValueError:
        raise SceneError('%s: expected a number, found %s' % (where, t))
    if not math.isfinite(x):
        raise SceneError('%s: %s is not finite' % (where, t))
    return x


def is_number(t):
    try:
        float(t)
        return True
    except ValueError:
        return False


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def rotation(ax, ay, az, deg):
    n = math.sqrt(ax * ax + ay * ay + az * az)
    x, y, z = ax / n, ay / n, az / n
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    t = 1 - c
    return [[t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0],
            [0, 0, 0, 1]]


def parse_scene(path):
    sc = Scene()
    sdir = os.path.dirname(os.path.abspath(path))
    lines = tokenize(path)
    i = 0
    while i < len(lines):
        n, t = lines[i]
        where = '%s:%d' % (path, n)
        i += 1
        kw = t[0]
        if kw == 'image':
            sc.width, sc.height = int(t[1]), int(t[2])
        elif kw == 'spp':
            sc.spp = int(t[1])
        elif kw == 'camera':
            d, k = {}, 1
            while k < len(t):
                if t[k] in ('position', 'direction'):
                    d[t[k]] = [num(x, where) for x in t[k + 1:k + 4]]
                    k += 4
                elif t[k] == 'fov':
                    d['fov'] = min(160.0, max(10.0, num(t[k + 1], where)))
                    k += 2
                else:
                    raise SceneError('%s: unknown camera clause %s' % (where, t[k]))
            sc.camera = (d['position'], d['direction'], d['fov'])
        elif kw == 'spectrum':
            name, how = t[1], t[2]
            if how == 'file':
                col = t[5] if len(t) > 5 and t[4] == 'column' else None
                wl, v = read_csv(find_spectrum_file(t[3], sdir), col)
                sc.spectra[name] = Spectrum(wl, v, 'data')
            elif how == 'equal':
                sc.spectra[name] = Spectrum([LMIN, LMAX], [1.0, 1.0], 'equal')
            elif how == 'blackbody':
                kel = num(t[3], where)
                wl = [LMIN + j for j in range(401)]
                sc.spectra[name] = Spectrum(wl, [planck(x, kel) for x in wl], 'blackbody')
            elif how == 'inline':
                vals = t[3:]
                while 'end' not in vals:
                    if i >= len(lines):
                        raise SceneError('%s: inline spectrum without end' % where)
                    vals += lines[i][1]
                    i += 1
                vals = [num(x, where) for x in vals[:vals.index('end')]]
                sc.spectra[name] = Spectrum(vals[0::2], vals[1::2], 'data')
            else:
                raise SceneError('%s: unknown spectrum kind %s' % (where, how))
        elif kw == 'material':
            sc.materials[t[1]] = parse_material(t, where, sc)
        elif kw == 'tri':
            p = [num(x, where) for x in t[2:11]]
            sc.tris.append((t[1], (p[0:3], p[3:6], p[6:9])))
        elif kw == 'quad':
            p = [num(x, where) for x in t[2:14]]
            a, b, c, d = p[0:3], p[3:6], p[6:9], p[9:12]
            sc.tris += [(t[1], (a, b, c)), (t[1], (a, c, d))]
        elif kw == 'mesh':
            sc.meshes.append(parse_mesh(t, where, sdir))
        elif kw == 'light':
            sc.lights.append(parse_light(t, where))
        elif kw == 'background':
            raise SceneError('%s: background is not converted (Mitsuba has no up/down sky)'
                             % where)
        else:
            raise SceneError('%s: unknown statement %s' % (where, kw))
    if sc.camera is None or sc.width is None:
        raise SceneError('%s: no camera or image' % path)
    return sc


def spot_solid_angle(c, b):
    """The solid angle of specmip's (and Mitsuba's) spot falloff, linear in the angle from
    the beam angle b to the cone c (radians): 2 pi (1 - (sin c - sin b) / (c - b))."""
    return 2 * math.pi * (1 - ((math.sin(c) - math.sin(b)) / (c - b) if c - b > 1e-6
                               else math.cos(c)))


def parse_light(t, where):
    """`light point|spot|distant ...` (docs/SCENE_FORMAT.md) as (kind, values): the
    position, target or direction, the spectrum's name and the intensity (or irradiance)
    per unit of the spectrum; a spot's cone and beam angles in degrees."""
    kind, k = t[1], 2
    vec = lambda: [num(x, where) for x in t[k:k + 3]]
    v = {}
    if kind in ('point', 'spot'):
        v['pos'] = vec()
        k += 3
    if kind == 'spot':
        v['target'] = vec()
        k += 3
    if kind == 'distant':
        v['dir'] = vec()
        k += 3
    if kind not in ('point', 'spot', 'distant'):
        raise SceneError('%s: light %s is not converted' % (where, kind))
    v['spectrum'] = t[k]
    k += 1
    power = None
    if t[k] == 'intensity':
        v['scale'] = num(t[k + 1], where)
    else:
        power = num(t[k], where)
    k += 2
    if kind == 'spot':
        if t[k] != 'cone':
            raise SceneError('%s: a spot light needs cone' % where)
        cone, k = num(t[k + 1], where), k + 2
        fall = cone / 4
        if k < len(t) and t[k] == 'falloff':
            fall, k = num(t[k + 1], where), k + 2
        if k < len(t) and t[k] == 'shape' and t[k + 1] != 'linear':
            raise SceneError('%s: only the linear falloff is Mitsuba\'s' % where)
        v['cone'], v['beam'] = cone, cone - fall
        if power is not None:
            v['scale'] = power / spot_solid_angle(math.radians(cone), math.radians(cone - fall))
    elif power is not None:
        v['scale'] = power / (4 * math.pi) if kind == 'point' else power
    return kind, v


def light_emitter(sc, kind, v):
    """Mitsuba's point, spot (its falloff is specmip's default, linear in angle) or
    directional emitter for a specmip light; the spectrum in Mitsuba's units as an area
    light's radiance (radiance())."""
    import mitsuba as mi
    spec = radiance(sc, (v['spectrum'], v['scale']))
    if kind == 'point':
        return {'type': 'point', 'position': v['pos'], 'intensity': spec}
    if kind == 'distant':
        return {'type': 'directional', 'direction': v['dir'], 'irradiance': spec}
    d = [v['target'][i] - v['pos'][i] for i in range(3)]
    up = [0, 1, 0] if abs(d[1]) < 0.9 * math.sqrt(sum(x * x for x in d)) else [1, 0, 0]
    return {'type': 'spot', 'intensity': spec, 'cutoff_angle': v['cone'],
            'beam_width': v['beam'],
            'to_world': mi.ScalarTransform4f().look_at(origin=v['pos'], target=v['target'],
                                                      up=up)}


def parse_material(t, where, sc):
    m = {'reflect': None, 'emit': None, 'conductor': None, 'dielectric': None}
    k = 2

    def spectrum_then_scale(k):
        name = t[k]
        if name not in sc.spectra:
            raise SceneError('%s: unknown spectrum %s' % (where, name))
        scale = 1.0
        if k + 1 < len(t) and is_number(t[k + 1]):
            scale = num(t[k + 1], where)
            k += 1
        return (name, scale), k + 1

    while k < len(t):
        if t[k] == 'reflect':
            m['reflect'], k = spectrum_then_scale(k + 1)
        elif t[k] == 'emit':
            m['emit'], k = spectrum_then_scale(k + 1)
        elif t[k] == 'twosided':
            raise SceneError('%s: twosided emitters are not converted' % where)
        elif t[k] == 'coated':
            k = coated_material(t, k + 1, where, m, spectrum_then_scale)
        elif t[k] == 'conductor':
            eta, k = spectrum_then_scale(k + 1)
            kk, k = spectrum_then_scale(k)
            alpha = None
            if k < len(t) and t[k] == 'alpha':
                alpha = num(t[k + 1], where)
                k += 2
            m['conductor'] = (eta, kk, alpha)
        elif t[k] == 'dielectric':
            ior, absorb, alpha = None, None, None
            k += 1
            while k < len(t) and t[k] in ('ior', 'absorb', 'alpha'):
                if t[k] == 'absorb':
                    absorb, k = spectrum_then_scale(k + 1)
                else:
                    v = num(t[k + 1], where)
                    ior, alpha = (v, alpha) if t[k] == 'ior' else (ior, v)
                    k += 2
            if ior is None:
                raise SceneError('%s: a dielectric needs ior' % where)
            m['dielectric'] = (ior, absorb, alpha)
        else:
            raise SceneError('%s: unknown material clause %s' % (where, t[k]))
    return m


def parse_mesh(t, where, sdir):
    f = t[1] if os.path.isabs(t[1]) else os.path.join(sdir, t[1])
    if os.path.splitext(f)[1].lower() not in ('.ply', '.obj'):
        raise SceneError('%s: only PLY and OBJ meshes are converted' % where)
    mat, m, k = None, [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], 2
    shading = None
    while k < len(t):
        c = t[k]
        if c == 'material':
            mat, k = t[k + 1], k + 2
            continue
        if c in ('smooth', 'flat'):
            shading, k = c, k + 1
            continue
        if c == 'scale':
            vals = t[k + 1:k + 4]
            try:
                s = [float(x) for x in vals]
                k += 4
            except ValueError:
                s = [float(t[k + 1])] * 3
                k += 2
            step = [[s[0], 0, 0, 0], [0, s[1], 0, 0], [0, 0, s[2], 0], [0, 0, 0, 1]]
        elif c == 'rotate':
            step, k = rotation(*[num(x, where) for x in t[k + 1:k + 5]]), k + 5
        elif c == 'translate':
            x, y, z = [num(v, where) for v in t[k + 1:k + 4]]
            step, k = [[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]], k + 4
        else:
            raise SceneError('%s: mesh clause %s is not converted' % (where, c))
        m = mat_mul(step, m)  # applied in the order written: m <- T m
    if mat is None:
        raise SceneError('%s: a converted mesh needs its material clause' % where)
    return (f, mat, m, shading)


def has_normals(path):
    """Whether a PLY's vertices carry nx ny nz, or an OBJ has vn lines and faces using them."""
    with open(path, 'rb') as f:
        if path.lower().endswith('.ply'):
            head = b''
            for line in f:
                head += line
                if line.strip() == b'end_header':
                    break
            return b'property float nx' in head or b'property double nx' in head
        data = f.read()
        return b'\nvn ' in data and b'/' in data  # f v//vn or v/vt/vn


def shades_smooth(sc, mesh):
    """specmip's rule (host/scene/mesh_build.c): the file's normals, when its material's
    type shades smooth by default (conductor, dielectric, coated) or the mesh says `smooth`,
    unless it says `flat`."""
    f, mat, _, shading = mesh
    if shading == 'flat' or not has_normals(f):
        return False
    m = sc.materials.get(mat, {})
    return shading == 'smooth' or bool(m.get('conductor') or m.get('dielectric') or
                                        m.get('coated'))


# ---------------------------------------------------------------- conversion

def irregular(wl, v, zero_outside=False):
    """A Mitsuba irregular spectrum; with zero_outside, 0 just outside 380-780 nm."""
    if zero_outside:
        wl = [LMIN - 1e-3] + list(wl) + [LMAX + 1e-3]
        v = [0.0] + list(v) + [0.0]
    return {'type': 'irregular', 'wavelengths': ', '.join('%.6f' % x for x in wl),
            'values': ', '.join('%.9g' % x for x in v)}


def reflectance(sc, ref):
    name, scale = ref
    s = sc.spectra[name]
    wl, v = clip_range(s.wl, s.v)
    return irregular(wl, [x * scale for x in v])


def radiance(sc, em):
    """specmip's emission (spectrum x SCALE / Y) in Mitsuba's units, zero outside 380-780."""
    name, scale = em
    s = sc.spectra[name]
    wl, v = clip_range(s.wl, s.v)
    ybar = cmf_y_bins()
    bins = bin_means(wl, v)
    y = sum(b * w for b, w in zip(bins, ybar)) / sum(ybar)
    if not y > 0:
        raise SceneError('emission %s has no luminance in 380-780 nm' % name)
    f = scale / y * CIE_Y_INTEGRAL_MITSUBA / sum(ybar)
    return irregular(wl, [x * f for x in v], zero_outside=True)


def coated_material(t, k, where, m, spectrum_then_scale):
    """The clauses after `coated` (reflect, ior, alpha, in any order; emit is the caller's)
    into m['coated'] = (reflectance, ior, alpha) and m['reflect']; returns the next index."""
    ior, alpha = 1.5, None  # specmip's default index (host/scene/coated.h)
    while k < len(t) and t[k] in ('reflect', 'ior', 'alpha'):
        if t[k] == 'reflect':
            m['reflect'], k = spectrum_then_scale(k + 1)
        elif t[k] == 'ior':
            ior, k = num(t[k + 1], where), k + 2
        else:
            alpha, k = num(t[k + 1], where), k + 2
    m['coated'] = (ior, alpha)
    return k


def coated_bsdf(sc, m):
    """Mitsuba's plastic / roughplastic for a coated material (nonlinear, ext_ior 1)."""
    ior, alpha = m['coated']
    if alpha is not None and alpha < SMOOTH_ALPHA:
        alpha = None  # specmip renders such widths as the smooth coating
    refl = reflectance(sc, m['reflect']) if m['reflect'] else {'type': 'spectrum', 'value': 0.0}
    inner = {'type': 'plastic' if alpha is None else 'roughplastic', 'int_ior': ior,
             'ext_ior': 1.0, 'nonlinear': True, 'diffuse_reflectance': refl}
    if alpha is not None:
        inner.update({'distribution': 'ggx', 'alpha': alpha, 'sample_visible': True})
    return {'type': 'twosided', 'bsdf': inner}


def bsdf(sc, m):
    if m.get('coated'):
        return coated_bsdf(sc, m)
    if m.get('dielectric'):
        ior, absorb, alpha = m['dielectric']
        if alpha is not None and alpha < SMOOTH_ALPHA:
            alpha = None
        # one-sided: the interior is behind the front face, as specmip's
        inner = {'type': 'dielectric' if alpha is None else 'roughdielectric',
                 'int_ior': ior, 'ext_ior': 1.0}
        if alpha is not None:
            inner.update({'distribution': 'ggx', 'alpha': alpha, 'sample_visible': True})
        return inner
    if m['conductor']:
        (eta, se), (k, sk), alpha = m['conductor']
        e, kk = sc.spectra[eta], sc.spectra[k]
        we, ve = clip_range(e.wl, e.v)
        wk, vk = clip_range(kk.wl, kk.v)
        if alpha is not None and alpha < SMOOTH_ALPHA:
            alpha = None  # specmip renders such widths as the smooth lobe
        inner = {'type': 'conductor' if alpha is None else 'roughconductor',
                 'eta': irregular(we, [x * se for x in ve]),
                 'k': irregular(wk, [x * sk for x in vk])}
        if alpha is not None:
            inner.update({'distribution': 'ggx', 'alpha': alpha, 'sample_visible': True})
    elif m['reflect']:
        inner = {'type': 'diffuse', 'reflectance': reflectance(sc, m['reflect'])}
    else:
        inner = {'type': 'diffuse', 'reflectance': {'type': 'spectrum', 'value': 0.0}}
    return {'type': 'twosided', 'bsdf': inner}


def write_ply(path, tris):
    """Binary PLY, three vertices per triangle (flat shading needs no shared ones)."""
    with open(path, 'wb') as f:
        f.write(('ply\nformat binary_little_endian 1.0\nelement vertex %d\n'
                 'property float x\nproperty float y\nproperty float z\n'
                 'element face %d\nproperty list uchar int vertex_indices\nend_header\n'
                 % (3 * len(tris), len(tris))).encode())
        for t in tris:
            for p in t:
                f.write(struct.pack('<3f', *p))
        for k in range(len(tris)):
            f.write(struct.pack('<B3i', 3, 3 * k, 3 * k + 1, 3 * k + 2))


MAX_DEPTH = -1  # Mitsuba's path length limit (-1: none); --max-depth sets it
INTEGRATOR = 'path'  # --integrator: path (Mitsuba's path) or light (its ptracer)


def convert(sc, outdir, spp, seed, width=None):
    """The Mitsuba scene dictionary (and its PLY files in outdir)."""
    import mitsuba as mi
    os.makedirs(outdir, exist_ok=True)
    w, h = sc.width, sc.height
    if width:
        h, w = max(1, round(h * width / w)), width
    pos, d, fov = sc.camera
    target = [pos[k] + d[k] for k in range(3)]
    scene = {
        'type': 'scene',
        'integrator': {'type': 'ptracer' if INTEGRATOR == 'light' else 'path',
                       'max_depth': MAX_DEPTH},
        'sensor': {
            'type': 'perspective', 'fov': fov, 'fov_axis': 'x',
            # specmip's image x runs along dir x up (world +x to the right when looking
            # along +z); Mitsuba's look_at puts up x dir on the left: mirror camera x
            'to_world': mi.ScalarTransform4f().look_at(origin=pos, target=target, up=[0, 1, 0])
            @ mi.ScalarTransform4f().scale([-1, 1, 1]),
            'film': {'type': 'hdrfilm', 'width': w, 'height': h, 'pixel_format': 'rgb',
                     'rfilter': {'type': 'box'}},
            'sampler': {'type': 'independent', 'sample_count': spp, 'seed': seed},
        },
    }
    by_mat = {}
    for m, t in sc.tris:
        by_mat.setdefault(m, []).append(t)
    shapes = [(m, {'type': 'ply', 'filename': os.path.join(outdir, 'tris_%s.ply' % m),
                   'face_normals': True}) for m in by_mat]
    for m, tris in by_mat.items():
        write_ply(os.path.join(outdir, 'tris_%s.ply' % m), tris)
    for mesh in sc.meshes:
        f, m, mat, _ = mesh
        kind = 'ply' if f.lower().endswith('.ply') else 'obj'
        shapes.append((m, {'type': kind, 'filename': f, 'to_world': mi.ScalarTransform4f(mat),
                           'face_normals': not shades_smooth(sc, mesh)}))
    for k, (m, shape) in enumerate(shapes):
        if m not in sc.materials:
            raise SceneError('unknown material %s' % m)
        mat = sc.materials[m]
        shape['bsdf'] = bsdf(sc, mat)
        if mat['dielectric'] and mat['dielectric'][1]:
            # Beer-Lambert inside: a purely absorbing homogeneous medium (albedo 0) of
            # extinction sigma = DENSITY SPEC per scene unit; needs the volpath integrator
            (name, dens) = mat['dielectric'][1]
            sp = sc.spectra[name]
            wl, v = clip_range(sp.wl, sp.v)
            # extended by its end values over Mitsuba's 360-830 nm (the lights are dark
            # there) and kept above 1e-6 per scene unit (a transmittance change below 1e-6
            # over any scene's objects): a zero extinction makes volpath's distance
            # sampling divide 0 by 0 (NaN pixels)
            wl, v = [350.0] + wl + [850.0], [v[0]] + v + [v[-1]]
            shape['interior'] = {'type': 'homogeneous', 'albedo': 0.0,
                                 'sigma_t': irregular(wl, [max(x * dens, 1e-6) for x in v])}
            scene['integrator']['type'] = 'volpath'
        if mat['emit']:
            shape['emitter'] = {'type': 'area', 'radiance': radiance(sc, mat['emit'])}
        scene['shape_%03d_%s' % (k, m)] = shape
    for k, (kind, v) in enumerate(sc.lights):
        scene['light_%03d_%s' % (k, kind)] = light_emitter(sc, kind, v)
    return scene


# ---------------------------------------------------------------- rendering, comparison

def render_mitsuba(sc, outdir, spp, seed, width, path):
    import mitsuba as mi
    t0 = time.time()
    scene = mi.load_dict(convert(sc, outdir, spp, seed, width))
    img = mi.render(scene, seed=seed, spp=spp)
    mi.Bitmap(img).write(path)
    return time.time() - t0


def absolute_copy(scene_path, out):
    """A copy of the scene whose spectrum and mesh files are absolute paths, resolved as this
    script resolves them (this tree's spectra/), so that a specmip binary built from another
    tree, whose data directory lacks a file, renders the same scene."""
    sdir = os.path.dirname(os.path.abspath(scene_path))
    lines = []
    with open(scene_path) as f:
        for line in f:
            toks = line.split('#', 1)[0].split()
            if len(toks) >= 4 and toks[0] == 'spectrum' and toks[2] == 'file':
                p = shlex.split(line.split('#', 1)[0])[3]
                line = line.replace(toks[3], shlex.quote(os.path.abspath(
                    find_spectrum_file(p, sdir))), 1)
            elif len(toks) >= 2 and toks[0] == 'mesh' and not os.path.isabs(toks[1]):
                line = line.replace(toks[1], shlex.quote(os.path.join(sdir, toks[1])), 1)
            lines.append(line)
    copy = os.path.join(out, os.path.basename(scene_path))
    with open(copy, 'w') as f:
        f.writelines(lines)
    return copy


def render_specmip(binary, scene_path, spp, seed, width, path, mode='truth'):
    cmd = [binary, 'render', scene_path, '--mode', mode, '--spp', str(spp), '--seed', str(seed),
           '--integrator', INTEGRATOR, '--quiet', '-o', path]
    if width:
        cmd += ['--width', str(width)]
    t0 = time.time()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return time.time() - t0


def compare(binary, ref, img, white_y=None):
    cmd = [binary, 'compare', ref, img, '--json']
    if white_y:
        cmd += ['--white-y', repr(white_y)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def mean_y(path):
    import mitsuba as mi
    import numpy as np
    a = np.array(mi.Bitmap(path), dtype=np.float64)
    return float(np.mean(0.2126 * a[..., 0] + 0.7152 * a[..., 1] + 0.0722 * a[..., 2]))


def de00_mean(j):
    return j['mean']  # specmip compare --json: CIEDE2000 statistics at the top level


def run_one(args, scene_path):
    import mitsuba as mi
    sc = parse_scene(scene_path)
    spp = args.spp
    name = os.path.splitext(os.path.basename(scene_path))[0]
    out = os.path.join(args.out, name)
    os.makedirs(out, exist_ok=True)
    m1, m2, sp = (os.path.join(out, f) for f in ('mitsuba_s1.exr', 'mitsuba_s2.exr',
                                                 'specmip_truth.exr'))
    t1 = render_mitsuba(sc, out, spp, 1, args.width, m1)
    t2 = render_mitsuba(sc, out, spp, 2, args.width, m2)
    ts = render_specmip(args.specmip, absolute_copy(scene_path, out), spp, 1, args.width, sp,
                        args.mode)
    c_floor = compare(args.specmip, m1, m2)
    white = c_floor['white_y']
    c_spec = compare(args.specmip, m1, sp, white)
    c_spec2 = compare(args.specmip, m2, sp, white)
    ym = 0.5 * (mean_y(m1) + mean_y(m2))
    ys = mean_y(sp)
    r = {'scene': name, 'spp': spp, 'size': '%dx%d' % tuple(mi.Bitmap(sp).size()),
         'mode': args.mode,
         'de_vs_s1': de00_mean(c_spec), 'de_vs_s2': de00_mean(c_spec2),
         'floor': de00_mean(c_floor), 'lum_ratio': ys / ym,
         'lum_seeds': mean_y(m2) / mean_y(m1), 'secs': (t1, t2, ts)}
    r['ratio'] = r['de_vs_s1'] / r['floor']
    r['pass'] = r['ratio'] <= 1.5 and abs(r['lum_ratio'] - 1) <= 0.01
    return r


def table(rows, md):
    head = ('scene', 'spp', 'size', 'specmip', 'dE00 vs M1', 'dE00 vs M2', 'floor M1-M2',
            'ratio', 'Y specmip/M', 'Y M2/M1', 'within', 's M1', 's specmip')
    lines = []
    for r in rows:
        lines.append((r['scene'], str(r['spp']), r['size'], r['mode'], '%.3f' % r['de_vs_s1'],
                      '%.3f' % r['de_vs_s2'], '%.3f' % r['floor'], '%.2f' % r['ratio'],
                      '%.4f' % r['lum_ratio'], '%.4f' % r['lum_seeds'],
                      'yes' if r['pass'] else 'NO', '%.1f' % r['secs'][0], '%.1f' % r['secs'][2]))
    if md:
        s = '| ' + ' | '.join(head) + ' |\n|' + '---|' * len(head) + '\n'
        return s + ''.join('| ' + ' | '.join(l) + ' |\n' for l in lines)
    wd = [max(len(x[k]) for x in [head] + lines) for k in range(len(head))]
    return '\n'.join('  '.join(c.ljust(wd[k]) for k, c in enumerate(l))
                     for l in [head] + lines) + '\n'


def check_ior():
    """The bundled metal_*.csv against the wheel's ior files: the same samples."""
    import mitsuba
    ior = os.path.join(os.path.dirname(mitsuba.__file__), 'data', 'ior')
    bad = 0
    files = sorted(glob.glob(os.path.join(ROOT, 'spectra', 'metal_*_*.csv')))
    for f in files:
        metal, q = os.path.basename(f)[6:-4].split('_')
        wl, v = read_csv(f)
        src = [tuple(map(float, l.split())) for l in open(os.path.join(ior, '%s.%s.spd'
                                                                      % (metal, q)))
               if l.strip() and not l.startswith('#')]
        inside = [p for p in src if wl[0] <= p[0] <= wl[-1]]
        same = len(inside) == len(wl) and all(abs(a - p[0]) < 1e-9 and abs(b - p[1]) < 1e-9
                                              for a, b, p in zip(wl, v, inside))
        covers = wl[0] < LMIN and wl[-1] > LMAX and \
            not any(wl[0] < p[0] < LMIN for p in src if p[0] < wl[0]) and \
            [p for p in src if p[0] < LMIN][-1][0] == wl[0] and \
            [p for p in src if p[0] > LMAX][0][0] == wl[-1]
        print('%-22s %2d samples %8.3f-%8.3f nm  %s' % (os.path.basename(f), len(wl), wl[0],
                                                       wl[-1], 'ok' if same and covers
                                                       else 'DIFFERS'))
        bad += not (same and covers)
    if not files:
        print('no spectra/metal_*.csv')
        return 1
    return 1 if bad else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('scenes', nargs='*')
    ap.add_argument('--spp', type=int, default=256)
    ap.add_argument('--width', type=int, default=128, help='image width (0: the scene\'s)')
    ap.add_argument('--specmip', default=os.path.join(ROOT, 'build', 'specmip'))
    ap.add_argument('--mode', default='truth', help='specmip mode to compare (default truth)')
    ap.add_argument('--out', default='mitsuba-out')
    ap.add_argument('--md', action='store_true', help='print the table as markdown')
    ap.add_argument('--max-depth', type=int, default=-1,
                    help="Mitsuba's max_depth (default -1: unlimited; specmip's record of 64 "
                         "vertices with a light sample at each is max_depth 65)")
    ap.add_argument('--integrator', choices=('path', 'light'), default='path',
                    help="path: Mitsuba's path against specmip's path tracer; light: Mitsuba's "
                         "ptracer against specmip's --integrator light")
    ap.add_argument('--check-ior', action='store_true')
    ap.add_argument('--convert-only', action='store_true')
    ap.add_argument('--mitsuba-only', action='store_true',
                    help='render Mitsuba (seed 1) alone into OUT/NAME/mitsuba_s1.exr')
    args = ap.parse_args()
    import mitsuba as mi
    mi.set_variant('scalar_spectral')
    global MAX_DEPTH, INTEGRATOR
    MAX_DEPTH = args.max_depth
    INTEGRATOR = args.integrator
    if args.check_ior:
        sys.exit(check_ior())
    if not args.scenes:
        ap.error('no scene given')
    try:
        if args.convert_only:
            for s in args.scenes:
                d = convert(parse_scene(s), args.out, args.spp, 1, args.width)
                with open(os.path.join(args.out, 'scene.json'), 'w') as f:
                    json.dump(d, f, indent=1, default=str)
                mi.load_dict(d)
                print('%s: converted into %s' % (s, args.out))
            return
        if args.mitsuba_only:
            for s in args.scenes:
                name = os.path.splitext(os.path.basename(s))[0]
                out = os.path.join(args.out, name)
                secs = render_mitsuba(parse_scene(s), out, args.spp, 1, args.width,
                                      os.path.join(out, 'mitsuba_s1.exr'))
                print('%s: %s (%.1f s)' % (s, os.path.join(out, 'mitsuba_s1.exr'), secs))
            return
        rows = []
        for s in args.scenes:
            rows.append(run_one(args, s))
            print(table(rows[-1:], False), file=sys.stderr, end='')
    except SceneError as e:
        print('mitsuba_compare: %s' % e, file=sys.stderr)
        sys.exit(2)
    print(table(rows, args.md), end='')
    sys.exit(0 if all(r['pass'] for r in rows) else 1)


if __name__ == '__main__':
    main()
