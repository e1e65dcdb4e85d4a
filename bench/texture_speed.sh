#!/usr/bin/env bash
# Paths/s of a textured scene against its twin with each texture's mean
# colour (docs/METHODS.md "Textures"), rendered in turn (A B A B ...) so the
# pairs share the machine's load; prints each pair's render-stage Mpaths/s
# (--stats) and their ratio. The twin: bench/texture_mean_scene.py.
# usage: bench/texture_speed.sh [build/specmip] [PAIRS] [SPP] (PYTHON with colour-science: build/pyenv)
set -eu
BIN=${1:-build/specmip} PAIRS=${2:-4} SPP=${3:-16}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
PY=${PYTHON:-$ROOT/build/pyenv/bin/python}
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
cp "$ROOT/scenes/textured.scene" "$T/a.scene"
"$PY" "$ROOT/bench/texture_mean_scene.py" "$ROOT/scenes/textured.scene" > "$T/b.scene" 2>/dev/null
rate() { "$BIN" render "$T/$1.scene" --mode ml --spp "$SPP" --stats -o "$T/$1.exr" 2>&1 |
         awk '$1 == "render" { print $4 }'; }
for i in $(seq "$PAIRS"); do
  a=$(rate a); b=$(rate b)
  echo "textured $a  mean-colour $b  ratio $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f", a / b }')"
done
