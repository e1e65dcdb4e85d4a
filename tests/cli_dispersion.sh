#!/bin/bash
# Dispersive glass (docs/METHODS.md "Dispersion"):
#  1. scenes/prism.scene, sf11_sphere.scene and prism_wall.scene are what
#     tools/gen_meshes.py --dispersion writes; the first two render in every
#     mode on both backends, with their glass in view (the glass made black
#     changes the image); prism_wall is tests/cli_light_prism.sh's;
#  2. deviation, closed form: in the prism's .spectral.exr at 1 nm (truth),
#     the image column of the slit at 450, 550 and 650 nm (the bins
#     [450, 451) nm ...) against the column where Snell's law with N-BK7's
#     n(lambda) (Schott's Sellmeier formula at the bin's centre, in double,
#     here) puts it, the geometry read from the scene: within a pixel;
#  3. a dispersive (N-SF11) sphere in a uniform background is invisible in
#     expectation: in truth, ml and hero every pixel's mean is the
#     background's, per channel, within five standard errors of the image's
#     own pixel spread (a wrong pdf or bin weight colours it), while the
#     sphere's pixels do carry the committed paths' colour noise;
#  4. a constant 'ior SPEC' renders glass.scene bit for bit as 'ior 1.5'.
# usage: bash tests/cli_dispersion.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
"$PY" -c 'import OpenImageIO, numpy' 2>/dev/null || { echo "SKIP: no Python with OpenImageIO and numpy ($PY)"; exit 77; }
hash_of() { oiiotool --hash "$1" | sed -n 's/.*SHA-1: *//p'; }

# the spheres the scenes place, beside the copies written here
cp "$DATA/scenes/materials_sphere.ply" "$T/"
# 1. generated scenes, every mode on both backends, glass in view
python3 "$ROOT/tools/gen_meshes.py" --dispersion "$T/gen" > "$T/gen.list" ||
    { echo "FAIL: gen_meshes.py --dispersion"; exit 1; }
n=0
for f in "$T"/gen/*.scene; do
    n=$((n + 1))
    check "$(basename "$f") is committed as generated" cmp -s "$f" "$DATA/scenes/$(basename "$f")"
done
check "gen_meshes.py --dispersion wrote 3 scenes ($n)" test "$n" -eq 3
R=(--quiet --width 40 --height 24 --spp 4 --seed 3)
for b in prism sf11_sphere; do
    f="$DATA/scenes/$b.scene"
    for be in opencl cpu; do
        for m in $("$BIN" modes | cut -f1); do
            "$BIN" render "$f" "${R[@]}" --backend $be --mode $m -o "$T/$b.$be.$m.exr" > /dev/null 2> "$T/err"
            rc=$?; check "$b $be $m: renders ($(head -c 300 "$T/err"))" test $rc -eq 0
        done
    done
    sed -E 's/^(material [a-z0-9]+) +dielectric .*/\1/' "$f" > "$T/$b.black.scene"
    "$BIN" render "$T/$b.black.scene" "${R[@]}" --mode truth -o "$T/$b.black.exr" > /dev/null 2>&1
    check "$b: the black variant renders" test $? -eq 0
    check "$b: the glass is in view" test "$(hash_of "$T/$b.opencl.truth.exr")" != "$(hash_of "$T/$b.black.exr")"
done

# 2. deviation against Snell's law (truth at 1 nm, 1024 spp: about 25 paths a
#    bin in the slit's column, its rows summed)
"$BIN" render "$DATA/scenes/prism.scene" --quiet --mode truth --spp 1024 --seed 5 --spectral-nm 1 \
    -o "$T/prism.exr" -o "$T/prism.spectral.exr" > /dev/null 2> "$T/err"
rc=$?; check "prism: truth at 1 nm renders ($(head -c 300 "$T/err"))" test $rc -eq 0
"$PY" - "$DATA/scenes/prism.scene" "$T/prism.spectral.exr" << 'PY' > "$T/dev.txt" 2>&1
import math, sys
import numpy as np, OpenImageIO as oiio
scene, exr = sys.argv[1:3]
# the scene: camera, the prism's cross-section (y = its lower end), the slit's centre
tris, slit, fov, w = [], None, None, None
for line in open(scene):
    t = line.split()
    if not t: continue
    if t[0] == 'image': w, h = int(t[1]), int(t[2])
    if t[0] == 'camera': fov = float(t[t.index('fov') + 1])
    if t[0] == 'tri' and t[1] == 'bk7': tris.append([float(x) for x in t[2:]])
    if t[0] == 'quad' and t[1] == 'slit':
        v = [float(x) for x in t[2:]]
        slit = (sum(v[0::3]) / 4, sum(v[2::3]) / 4)
ylo = min(min(t[1::3]) for t in tris)
pts = sorted({(round(t[3 * k], 6), round(t[3 * k + 2], 6)) for t in tris for k in range(3)
              if abs(t[3 * k + 1] - ylo) < 1e-9})
assert len(pts) == 3, pts
zf = min(z for x, z in pts)
front = [p for p in pts if abs(p[1] - zf) < 1e-9]          # the face square to the view
apex = [p for p in pts if p not in front][0]
pb = max(front)                                             # the back face: pb to apex
c = (sum(x for x, z in pts) / 3, sum(z for x, z in pts) / 3)
def n_bk7(nm):  # Schott N-BK7, Sellmeier (um)
    l2 = (nm * 1e-3) ** 2
    B, C = (1.03961212, 0.231792344, 1.01046945), (0.00600069867, 0.0200179144, 103.560653)
    return math.sqrt(1 + sum(b * l2 / (l2 - cc) for b, cc in zip(B, C)))
def refract(d, nrm, e):  # d unit, nrm unit facing d's origin, e = n_t / n_i
    ci = -(d[0] * nrm[0] + d[1] * nrm[1])
    s2 = (1 - ci * ci) / (e * e)
    ct = math.sqrt(1 - s2)
    return (d[0] / e + nrm[0] * (ci / e - ct), d[1] / e + nrm[1] * (ci / e - ct))
def hit_line(o, d, a, b):  # o + t d on the line a-b
    ex, ez = b[0] - a[0], b[1] - a[1]
    den = d[0] * ez - d[1] * ex
    t = ((a[0] - o[0]) * ez - (a[1] - o[1]) * ex) / den
    return (o[0] + t * d[0], o[1] + t * d[1])
def miss(u, n):  # which side of the slit the ray of image column u passes (x, z plane)
    cx = 2 * u / w - 1
    d = (math.tan(math.radians(fov) / 2) * cx, 1.0)
    l = math.hypot(*d); d = (d[0] / l, d[1] / l)
    p = hit_line((0.0, 0.0), d, front[0], front[1])
    d = refract(d, (0.0, -1.0), n)
    q = hit_line(p, d, pb, apex)
    ex, ez = apex[0] - pb[0], apex[1] - pb[1]
    nb = (ez, -ex); l = math.hypot(*nb); nb = (nb[0] / l, nb[1] / l)
    if nb[0] * (q[0] - c[0]) + nb[1] * (q[1] - c[1]) < 0: nb = (-nb[0], -nb[1])  # outward
    d = refract(d, (-nb[0], -nb[1]), 1 / n)
    return d[0] * (slit[1] - q[1]) - d[1] * (slit[0] - q[0])
def column(n):  # bisection on the continuous column u in [0, w]
    lo, hi = 0.0, float(w)
    assert miss(lo, n) * miss(hi, n) < 0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if miss(lo, n) * miss(mid, n) <= 0: hi = mid
        else: lo = mid
    return 0.5 * (lo + hi)
img = oiio.ImageInput.open(exr)
names = img.spec().channelnames
a = np.array(img.read_image(format='float')); img.close()
bad = 0
for nm in (450, 550, 650):
    ch = names.index('S0.%d,5nm' % nm)
    col = a[:, :, ch].sum(axis=0)
    k = int(np.argmax(col))
    lo, hi = max(k - 3, 0), min(k + 4, w)
    got = float(((np.arange(lo, hi) + 0.5) * col[lo:hi]).sum() / col[lo:hi].sum()) if col[lo:hi].sum() > 0 else float('nan')
    want = column(n_bk7(nm + 0.5))
    ok = abs(got - want) <= 1.0
    bad += not ok
    print('%d nm: n %.6f, slit at column %.2f (Snell %.2f), %s' % (nm, n_bk7(nm + 0.5), got, want, 'ok' if ok else 'OFF'))
print('spread 450-650 nm: %.2f columns' % (column(n_bk7(450.5)) - column(n_bk7(650.5))))
sys.exit(1 if bad else 0)
PY
rc=$?
sed 's/^/  /' "$T/dev.txt"
check "prism: 450, 550, 650 nm within a pixel of Snell's law" test $rc -eq 0

# 3. the invisible sphere: N-SF11 in a background of one emission everywhere
cat > "$T/inv.scene" << 'SCENE'
image 32 32
camera position 0 0 -3  direction 0 0 1  fov 40
spectrum equal  equal
material sf11  dielectric glass N-SF11
background both equal 1
SCENE
"$PY" - >> "$T/inv.scene" << 'PY'
import math
def pt(i, j, rings=12, segs=24, r=0.8):
    th, ph = math.pi * i / rings, 2 * math.pi * (j + 0.5 * (i % 2)) / segs
    return (r * math.sin(th) * math.cos(ph), r * math.cos(th), r * math.sin(th) * math.sin(ph))
def out(t):  # front face away from the centre
    (a, b, c) = t
    e1 = [b[k] - a[k] for k in range(3)]; e2 = [c[k] - a[k] for k in range(3)]
    n = (e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0])
    return t if sum(n[k] * (a[k] + b[k] + c[k]) for k in range(3)) > 0 else (a, c, b)
for i in range(12):
    for j in range(24):
        a, b, c, d = pt(i, j), pt(i, j + 1), pt(i + 1, j), pt(i + 1, j + 1)
        ts = []
        if i > 0: ts.append((a, b, d) if i % 2 == 0 else (a, b, c))
        if i < 11: ts.append((a, d, c) if i % 2 == 0 else (b, d, c))
        for t in ts:
            print('tri sf11 ' + '  '.join(' '.join('%.6f' % x for x in v) for v in out(t)))
PY
for m in truth ml hero; do
    "$BIN" render "$T/inv.scene" --quiet --mode $m --spp 64 --seed 9 -o "$T/inv.$m.exr" > /dev/null 2> "$T/err"
    rc=$?; check "invisible sphere $m: renders ($(head -c 300 "$T/err"))" test $rc -eq 0
done
"$PY" - "$T"/inv.truth.exr "$T"/inv.ml.exr "$T"/inv.hero.exr << 'PY' > "$T/inv.txt" 2>&1
import sys
import numpy as np, OpenImageIO as oiio
def load(p):
    i = oiio.ImageInput.open(p); a = np.array(i.read_image(format='float'))[:, :, :3]; i.close()
    return a.reshape(-1, 3).astype(np.float64)
truth = load(sys.argv[1])
# the background: the corner pixels' truth (paths that miss the sphere see it exactly)
bg = truth[0]
corners = truth[[0, 31, 32 * 31, 32 * 32 - 1]]
bad = int(np.abs(corners - bg).max() > 1e-6 * np.abs(bg).max())
print('background %s' % bg)
for p in sys.argv[1:]:
    a = load(p)
    se = a.std(axis=0, ddof=1) / np.sqrt(len(a))
    z = (a.mean(axis=0) - bg) / se
    centre = a.reshape(32, 32, 3)[12:20, 12:20].reshape(-1, 3)
    # the committed paths' colour noise, relative to the background: 4.9e-4 at
    # 64 spp with the wavelengths stratified over the pixel's samples (the
    # strata's quadrature error), 9.8e-8 for the same sphere of one index
    # (float rounding of weight-1 paths): 1e-5 sits 50x from each
    noisy = centre.std(axis=0).max() > 1e-5 * np.abs(bg).max()
    ok = np.all(np.abs(z) <= 5) and noisy
    bad += not ok
    print('%s: mean %s, %s standard errors from it; sphere pixel spread %s: %s' % (
        p.split('.')[-2], a.mean(axis=0), np.round(z, 2), centre.std(axis=0), 'ok' if ok else 'OFF'))
sys.exit(1 if bad else 0)
PY
rc=$?
sed 's/^/  /' "$T/inv.txt"
check "invisible sphere: truth, ml, hero means are the background's" test $rc -eq 0

# 4. a constant 'ior SPEC' is 'ior N', bit for bit
sed -E 's/ ior 1\.5/ ior n15/; s/^(spectrum equal .*)$/\1\nspectrum n15 inline 380 1.5 580 1.5 780 1.5 end/' \
    "$DATA/scenes/glass.scene" > "$T/glass_const.scene"
check "the constant-index variant differs in its text" test "$(grep -c 'ior n15' "$T/glass_const.scene")" -eq 3
for be in opencl cpu; do
    for m in truth ml hero rgb; do
        "$BIN" render "$DATA/scenes/glass.scene" --quiet --backend $be --mode $m --width 24 --height 16 --spp 4 --seed 7 -o "$T/g.exr" > /dev/null 2>&1
        "$BIN" render "$T/glass_const.scene" --quiet --backend $be --mode $m --width 24 --height 16 --spp 4 --seed 7 -o "$T/gc.exr" > /dev/null 2>&1
        ha=$(hash_of "$T/g.exr") hb=$(hash_of "$T/gc.exr")
        check "constant ior SPEC, $be $m: the same pixels ($ha, $hb)" test -n "$ha" -a "$ha" = "$hb"
        rm -f "$T/g.exr" "$T/gc.exr"
    done
done
finish
