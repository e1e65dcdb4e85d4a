#!/bin/bash
# specmip spectrum: JSON output of good files parses and holds sane values;
# the levels table and the pretest's choice agree with a recomputation from
# the colours it prints at each level;
# every tests/bad-inputs/*.csv exits 2 naming the file and the line that its
# first comment line announces ("... line N ..."); a directory is refused as one.
# usage: bash tests/cli_spectrum.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

# One reflectance, checked in Python: keys present, white patch near Y = 88.7
# (Ohta's white_9_5 under D65), near neutral, the five levels and their bins.
out=$("$BIN" spectrum "$ROOT/spectra/colorchecker_n_ohta.csv" --column white_9_5 --json)
if [ $? -eq 0 ] && python3 -c '
import json, sys
d = json.loads(sys.argv[1])
for k in ("XYZ", "Lab", "sRGB", "levels", "chosen_level"):
    assert k in d, k
assert abs(d["XYZ"][1] - 88.7) < 0.5, d["XYZ"]          # README: Y ~ 88.7
assert abs(d["Lab"][1]) < 2 and abs(d["Lab"][2]) < 3, d["Lab"]  # near neutral
assert [l["bins"] for l in d["levels"]] == [400, 80, 40, 20, 10]
# level_k: one level per occurrence count a path can have (records of 64 vertices)
assert d["chosen_level"] in (0, 1, 2, 3) and len(d["level_k"]) == 64
' "$out"; then ok; else bad "white_9_5 JSON: $out"; fi

# The levels table and the pretest against a recomputation here from the XYZ
# that --level prints (the level's colour, the light kept at level 0, 1 nm):
# - a reflectance's level-l dE00 and dEab are those of its level-l colour
#   against its level-0 colour, under the CIELAB white of the same light;
# - a light alone is pretested on its own (README: its error at level l is
#   the colour difference of level l against level 0, both scaled by the
#   factor that takes level 0 to Y = 50, against the D65 white of Y = 100), so the chosen level, and every level_k,
#   is the coarsest of 1..3 whose error is within the threshold: tried at 0,
#   at a huge threshold and just below and above each error;
# - a flat reflectance samples exactly at every level: level 3 even at
#   threshold 0; a coloured one fails at 0 and passes a huge threshold.
printf 'wavelength_nm,value\n380,1\n780,1\n' > "$T/one.csv"
printf 'wavelength_nm,value\n380,0.5\n780,0.5\n' > "$T/half.csv"
if python3 - "$BIN" "$ROOT" "$T" <<'EOF'; then ok; else bad "levels and pretest against their recomputation"; fi
import json, math, subprocess, sys
BIN, ROOT, T = sys.argv[1:4]
fails = []
def check(cond, what):
    if not cond:
        fails.append(what)
def spectrum(*args):
    out = subprocess.run([BIN, "spectrum", *args, "--json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)
def lab(xyz, white):
    f = lambda t: t ** (1 / 3) if t > (6 / 29) ** 3 else t / (3 * (6 / 29) ** 2) + 4 / 29
    fx, fy, fz = (f(xyz[i] / white[i]) for i in range(3))
    return (116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz))
def de_ab(p, q):
    return math.dist(p, q)
def de00(p, q):  # CIEDE2000 as Sharma, Wu and Dalal (2005) give it
    (L1, a1, b1), (L2, a2, b2) = p, q
    cb7 = ((math.hypot(a1, b1) + math.hypot(a2, b2)) / 2) ** 7
    g = 0.5 * (1 - math.sqrt(cb7 / (cb7 + 25 ** 7)))
    a1, a2 = (1 + g) * a1, (1 + g) * a2
    c1, c2 = math.hypot(a1, b1), math.hypot(a2, b2)
    h1 = math.degrees(math.atan2(b1, a1)) % 360 if c1 else 0.0
    h2 = math.degrees(math.atan2(b2, a2)) % 360 if c2 else 0.0
    dh = 0.0 if c1 * c2 == 0 else (h2 - h1 + 180) % 360 - 180
    dH = 2 * math.sqrt(c1 * c2) * math.sin(math.radians(dh / 2))
    lm, cm = (L1 + L2) / 2, (c1 + c2) / 2
    if c1 * c2 == 0:
        hm = h1 + h2
    elif abs(h1 - h2) <= 180:
        hm = (h1 + h2) / 2
    else:
        hm = (h1 + h2 + (360 if h1 + h2 < 360 else -360)) / 2
    t = (1 - 0.17 * math.cos(math.radians(hm - 30)) + 0.24 * math.cos(math.radians(2 * hm))
         + 0.32 * math.cos(math.radians(3 * hm + 6)) - 0.20 * math.cos(math.radians(4 * hm - 63)))
    rt = (-math.sin(math.radians(60 * math.exp(-(((hm - 275) / 25) ** 2))))
          * 2 * math.sqrt(cm ** 7 / (cm ** 7 + 25 ** 7)))
    sl = 1 + 0.015 * (lm - 50) ** 2 / math.sqrt(20 + (lm - 50) ** 2)
    sc, sh = 1 + 0.045 * cm, 1 + 0.015 * cm * t
    dl, dc, dh_ = (L2 - L1) / sl, (c2 - c1) / sc, dH / sh
    return math.sqrt(dl * dl + dc * dc + dh_ * dh_ + rt * dc * dh_)
# Sharma et al.'s table, pairs 1 and 17, checks the formula itself
check(abs(de00((50, 2.6772, -79.7751), (50, 0, -82.7485)) - 2.0425) < 1e-4, "dE00 pair 1")
check(abs(de00((50, 2.5, 0), (73, 25, -18)) - 27.1492) < 1e-4, "dE00 pair 17")
# XYZ and errors are printed with 6 decimals on values up to ~100: a few 1e-6
# of rounding, which dE (slopes of order 1 in XYZ near Y = 50) keeps below 1e-4.
TOL = 1e-4
CC = f"{ROOT}/spectra/colorchecker_n_ohta.csv"

for patch in ("white_9_5", "red"):
    for light in ("D65", "F11"):
        white = spectrum(f"{T}/one.csv", "--illuminant", light, "--level", "0")["XYZ"]
        at = [spectrum(CC, "--column", patch, "--illuminant", light, "--level", str(l))
              for l in range(5)]
        lab0 = lab(at[0]["XYZ"], white)
        for l in range(1, 5):
            labl = lab(at[l]["XYZ"], white)
            got = at[0]["levels"][l]
            check(abs(got["dE00"] - de00(lab0, labl)) < TOL,
                  f"{patch} under {light}: level {l} dE00 {got['dE00']} vs {de00(lab0, labl)}")
            check(abs(got["dEab"] - de_ab(lab0, labl)) < TOL,
                  f"{patch} under {light}: level {l} dEab {got['dEab']} vs {de_ab(lab0, labl)}")

d65 = spectrum(f"{ROOT}/spectra/illuminant_D65_1nm.csv", "--emission")["XYZ"]
def at_y50(xyz, y0):  # scaled by the factor that takes level 0 (y0) to Y = 50
    return [v * 50 / y0 for v in xyz]
nchecked = 0
for name, metric in (("illuminant_F11", "de00"), ("illuminant_F11", "deab"),
                     ("illuminant_A", "de00"), ("lightsource_nist_mercury", "de00"),
                     ("illuminant_LED_B1", "de00")):
    f = f"{ROOT}/spectra/{name}.csv"
    xyz = [spectrum(f, "--emission", "--level", str(l))["XYZ"] for l in range(4)]
    de = de00 if metric == "de00" else de_ab
    err = [de(lab(at_y50(xyz[0], xyz[0][1]), d65), lab(at_y50(xyz[l], xyz[0][1]), d65))
           for l in range(4)]
    thresholds = [0.0, 1e6] + [e * g for e in err[1:] if e > 100 * TOL for g in (0.99, 1.01)]
    for thr in thresholds:
        d = spectrum(f, "--emission", "--metric", metric, "--threshold", repr(thr))
        want = max([0] + [l for l in (1, 2, 3) if err[l] <= thr])
        check(d["chosen_level"] == want and d["level_k"] == [want] * 64,
              f"{name} ({metric}) at threshold {thr}: level {d['chosen_level']}, "
              f"level_k {d['level_k']}; errors {err[1]:.6f} {err[2]:.6f} {err[3]:.6f} say {want}")
        nchecked += 1
check(nchecked >= 25, f"only {nchecked} thresholds tried")

check(spectrum(f"{T}/half.csv", "--threshold", "0")["chosen_level"] == 3, "flat: level 3 at 0")
w = [spectrum(CC, "--column", "white_9_5", "--threshold", t)["chosen_level"] for t in ("0", "1e6")]
check(w == [0, 3], f"white_9_5 at thresholds 0 and 1e6: levels {w}")
for f in fails:
    print("FAIL:", f, file=sys.stderr)
sys.exit(1 if fails else 0)
EOF

# Several columns -> an array, one object per patch; F11 as an emission.
out=$("$BIN" spectrum "$ROOT/spectra/colorchecker_n_ohta.csv" --illuminant F11 --json)
if [ $? -eq 0 ] && python3 -c '
import json, sys
d = json.loads(sys.argv[1])
assert isinstance(d, list) and len(d) == 24, len(d)
assert all(p["illuminant"] == "F11" for p in d)
' "$out"; then ok; else bad "ColorChecker array"; fi
out=$("$BIN" spectrum "$ROOT/spectra/illuminant_F11.csv" --emission --json --metric deab --threshold 1)
if [ $? -eq 0 ] && python3 -c '
import json, sys
d = json.loads(sys.argv[1])
assert d["kind"] == "emission" and abs(d["XYZ"][1] - 100) < 1e-6 and d["metric"] == "deab"
' "$out"; then ok; else bad "F11 emission: $out"; fi

# Text output and --help.
"$BIN" spectrum "$ROOT/spectra/illuminant_A.csv" --emission | grep -q "chosen level" && ok || bad "text output"
"$BIN" spectrum --help | grep -q -- "--illuminant" && ok || bad "--help"
"$BIN" spectrum "$ROOT/spectra/illuminant_A.csv" --bogus >/dev/null 2>&1
[ $? -eq 2 ] && ok || bad "unknown option must exit 2"
"$BIN" spectrum "$ROOT/spectra/colorchecker_n_ohta.csv" --illuminant nosuchlight >/dev/null 2>&1
[ $? -eq 2 ] && ok || bad "unknown illuminant must exit 2"

# Bad inputs.
n=0
for f in "$ROOT"/tests/bad-inputs/*.csv; do
    n=$((n + 1))
    line=$(head -n 1 "$f" | sed -n 's/.*line \([0-9][0-9]*\).*/\1/p')
    msg=$("$BIN" spectrum "$f" 2>&1 >/dev/null)
    rc=$?
    name=$(basename "$f")
    if [ $rc -eq 2 ] && [[ "$msg" == *"$name:$line:"* ]] && [ -n "$line" ]; then ok
    else bad "$name: exit $rc, message '$msg', expected '$name:$line:'"; fi
done
[ $n -ge 7 ] && ok || bad "only $n bad inputs"

# A directory is named as one, given as the spectrum and as a scene's spectrum file.
msg=$("$BIN" spectrum "$T" 2>&1 >/dev/null); rc=$?
[ $rc -eq 2 ] && [[ "$msg" == *"$T: is a directory"* ]] && ok || bad "directory as a spectrum: exit $rc, '$msg'"
msg=$("$BIN" render "$ROOT/tests/bad-inputs/scene_directory_spectrum.scene" -o "$T/x.png" 2>&1); rc=$?
[ $rc -eq 2 ] && [[ "$msg" == *"scene_directory_spectrum.scene:6:"*"is a directory"* ]] && ok ||
  bad "directory as a scene's spectrum file: exit $rc, '$msg'"

finish
