#!/usr/bin/env bash
# ml against truth on the textured box (docs/METHODS.md "Levels for textured
# factors"): scenes/textured.scene as it is (an equal-energy lamp) and a
# variant under CIE F11 with saturated floor and short-box checkers (red and
# green, yellow and blue), the same seed and samples in both modes, so the
# images differ only by the levels; prints `specmip compare`'s lines.
# usage: bench/texture_ml.sh [build/specmip] [SPP] [OUTDIR]
set -eu
BIN=${1:-build/specmip} SPP=${2:-256} OUT=${3:-texture_ml}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$OUT"
cp "$ROOT/scenes/textured.scene" "$OUT/equal.scene"
sed -e 's/^material light     reflect white  emit equal 1000/spectrum f11 file illuminant_F11.csv\nmaterial light     reflect white  emit f11 1000/' \
    -e 's/^spectrum equal     equal$//' \
    -e 's/^texture floor   checker 16 .*/texture floor   checker 16  0.90 0.05 0.05  0.05 0.85 0.10/' \
    -e 's/^texture short   checker 4 .*/texture short   checker 4   0.95 0.85 0.02  0.02 0.05 0.90/' \
    "$ROOT/scenes/textured.scene" > "$OUT/f11.scene"
for s in equal f11; do
  for m in truth ml; do
    "$BIN" render "$OUT/$s.scene" --mode $m --seed 7 --spp "$SPP" --width 128 --height 128 \
      --quiet -o "$OUT/$s-$m.exr"
  done
  echo "$s:"; "$BIN" compare "$OUT/$s-truth.exr" "$OUT/$s-ml.exr" | sed -n 2,3p
done
