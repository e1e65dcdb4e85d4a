#!/bin/bash
# The scene example in README.md parses and renders (CPU reference, tiny size),
# so the documentation cannot drift from the parser.
# usage: bash tests/cli_readme_example.sh /path/to/specmip
set -u
BIN=${1:?usage: cli_readme_example.sh SPECMIP}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
export SPECMIP_DATA=${SPECMIP_DATA:-$ROOT}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
# the first fenced block after "## Scenes"
awk '/^## Scenes/{s=1} s&&/^```/{if(b){exit}else{b=1;next}} b' "$ROOT/README.md" > "$T/example.scene"
pass=0 fail=0
if grep -q '^camera' "$T/example.scene"; then pass=$((pass+1)); else fail=$((fail+1)); echo "FAIL: no example found" >&2; fi
if "$BIN" render "$T/example.scene" --backend cpu --spp 1 --width 16 --height 16 -o "$T/x.exr" --quiet; then
  pass=$((pass+1)); else fail=$((fail+1)); echo "FAIL: README example does not render" >&2; fi
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
