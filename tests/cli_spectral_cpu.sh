#!/usr/bin/env bash
# Spectral images out on the CPU reference (no OpenCL, so the sanitizer
# build runs it too): every spectral mode's .spectral.exr read back and
# checked as cli_render_spectral.sh does on the OpenCL backend, and rgb
# refused before rendering.
source "$(dirname "$0")/lib_cli.sh"
source "$(dirname "$0")/lib_spectral.sh"

modes_on cpu
rm -f "$T"/r.*
timeout 60 "$BIN" render "$SCENE" --backend cpu --spp 1000000 --mode rgb -o "$T/r.spectral.exr" \
    2> "$T/err"
check "rgb: exit 2" test $? -eq 2
check "rgb: says why" grep -q "rgb mode has no spectrum" "$T/err"
check "rgb: nothing written" test -z "$(ls "$T"/r.* 2> /dev/null)"
finish
