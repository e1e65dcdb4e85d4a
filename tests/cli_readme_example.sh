#!/bin/bash
# The scene example in README.md parses and renders (CPU reference, tiny size),
# so the documentation cannot drift from the parser.
# usage: bash tests/cli_readme_example.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
# the first fenced block after "## Scenes"
awk '/^## Scenes/{s=1} s&&/^```/{if(b){exit}else{b=1;next}} b' "$ROOT/README.md" > "$T/example.scene"
check "README has a scene example" grep -q '^camera' "$T/example.scene"
check "README example renders" "$BIN" render "$T/example.scene" --backend cpu --spp 1 --width 16 \
    --height 16 -o "$T/x.exr" --quiet
finish
