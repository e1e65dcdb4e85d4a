#!/bin/bash
# The level the pretest picks for every bundled spectrum at thresholds 1, 2
# and 5 (dE00), as a markdown table: lights on their own, ColorChecker patches
# under D65 (each with the light only, as `specmip spectrum` runs it).
# usage: tools/pretest_table.sh [path/to/specmip]   (default build/specmip)
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$ROOT/build/specmip}
export SPECMIP_DATA=${SPECMIP_DATA:-$ROOT}
THRESHOLDS="1 2 5"

# Prints "name<TAB>level" lines for one file at one threshold.
levels() { # file threshold [extra options]
    local f=$1 t=$2
    shift 2
    "$BIN" spectrum "$f" --threshold "$t" --json "$@" | python3 -c '
import json, sys
d = json.load(sys.stdin)
for r in d if isinstance(d, list) else [d]:
    name = r["name"].rsplit("/", 1)[-1]
    name = name.replace(".csv:", ":") if ".csv:" in name else name[:-4]
    print(name + "\t" + str(r["chosen_level"]))
'
}

table() { # kind file [options]: joins the per-threshold columns
    local kind=$1 f=$2
    shift 2
    local tmp
    tmp=$(mktemp -d)
    for t in $THRESHOLDS; do levels "$f" "$t" "$@" > "$tmp/$t"; done
    paste $(for t in $THRESHOLDS; do echo "$tmp/$t"; done) |
        awk -F'\t' -v kind="$kind" '{ printf "| %s | %s |", $1, kind; for (i = 2; i <= NF; i += 2) printf " %s |", $i; print "" }'
    rm -r "$tmp"
}

echo "| spectrum | kind | level at dE00 1 | at 2 | at 5 |"
echo "|---|---|---|---|---|"
for f in "$ROOT"/spectra/illuminant_*.csv "$ROOT"/spectra/lightsource_*.csv; do
    table "light, alone" "$f" --emission
done
table "reflectance under D65" "$ROOT/spectra/colorchecker_n_ohta.csv" --illuminant D65
echo
echo "Levels: 0 = 80 bins (5 nm), 1 = 40 bins, 2 = 20 bins (the coarsest the pretest picks by default)."
echo "Produced by: tools/pretest_table.sh $(basename "$BIN")"
