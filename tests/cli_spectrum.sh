#!/bin/bash
# specmip spectrum: JSON output of good files parses and holds sane values;
# every tests/bad-inputs/*.csv exits 2 naming the file and the line that its
# first comment line announces ("... line N ..."); a directory is refused as one.
# usage: bash tests/cli_spectrum.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

# One reflectance, checked in Python: keys present, white patch near Y = 88.7
# (Ohta's white_9_5 under D65, /work/shared/data/README.md), levels ordered.
out=$("$BIN" spectrum "$ROOT/spectra/colorchecker_n_ohta.csv" --column white_9_5 --json)
if [ $? -eq 0 ] && python3 -c '
import json, sys
d = json.loads(sys.argv[1])
for k in ("XYZ", "Lab", "sRGB", "levels", "chosen_level"):
    assert k in d, k
assert abs(d["XYZ"][1] - 88.7) < 0.5, d["XYZ"]          # README: Y ~ 88.7
assert abs(d["Lab"][1]) < 2 and abs(d["Lab"][2]) < 3, d["Lab"]  # near neutral
assert [l["bins"] for l in d["levels"]] == [80, 40, 20, 10]
assert d["levels"][0]["dE00"] == 0 and all(l["dE00"] >= 0 for l in d["levels"])
assert d["chosen_level"] in (0, 1, 2)
' "$out"; then ok; else bad "white_9_5 JSON: $out"; fi

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
