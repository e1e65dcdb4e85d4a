#!/usr/bin/env bash
# Spectral images out (-o NAME.spectral.exr): each spectral mode on the
# OpenCL backend (cli_spectral_cpu.sh: the CPU reference) writes a file that tests/spectral_check.cpp reads back with
# OpenImageIO and checks against independent computations: its integral with
# the CIE 1931 CMFs against the XYZ film of the same render (the .exr written
# beside it), a pixel that sees the F11 lamp of tests/data/scenes/lamp_wall.scene
# against the lamp's spectrum at luminance 1000; rgb and unsupported bin
# widths are refused before rendering; an interrupted render writes a valid
# spectral file of the passes done. A film too large for this machine's
# memory: cli_render_spectral_memory.sh; colour-science reading the files:
# cli_render_spectral_colour.sh.
source "$(dirname "$0")/lib_cli.sh"

source "$(dirname "$0")/lib_spectral.sh"

modes_on opencl
check "1 nm file: 400 bins" grep -q "400 bins of 1 nm" <("$CHECK" "$T/truth1-opencl.spectral.exr" --cmf "$CMF")

# refused WHAT MESSAGE ARGS...: exit 2 before rendering (a render that would
# outlast the timeout), the message said, no file written.
refused() {
    local what=$1 msg=$2
    shift 2
    rm -f "$T"/r.*
    timeout 60 "$BIN" render "$SCENE" --spp 1000000 --quiet "$@" 2> "$T/err"
    local rc=$?
    check "$what: exit 2 (got $rc)" test $rc -eq 2
    check "$what: says '$msg'" grep -q -- "$msg" "$T/err"
    check "$what: nothing written" test -z "$(ls "$T"/r.* 2> /dev/null)"
}
refused "rgb" "rgb mode has no spectrum" --mode rgb -o "$T/r.spectral.exr" -o "$T/r.exr"
refused "ref at 1 nm" "ref mode writes 5 nm bins only" --mode ref --spectral-nm 1 \
    -o "$T/r.spectral.exr"
refused "--spectral-nm 2" "is 1 or 5" --mode truth --spectral-nm 2 -o "$T/r.spectral.exr"
refused "--spectral-nm alone" "needs a .spectral.exr output" --spectral-nm 5 -o "$T/r.exr"
# Interrupted: a render of many passes stopped after its first, both files
# written from the same film of the passes done.
"$BIN" render "$SCENE" --mode ref --spp 100000 --progress -o "$T/i.exr" -o "$T/i.spectral.exr" \
    > /dev/null 2> "$T/ierr" &
pid=$!
if rendering $pid "$T/ierr"; then
    kill -INT $pid
    wait $pid
    rc=$?
    check "interrupted: exit 130 (got $rc)" test $rc -eq 130
    "$CHECK" "$T/i.spectral.exr" --cmf "$CMF" --xyz "$T/i.exr" $EXACT \
        --lamp "$F11" 1000 "${LAMP[@]}" $EXACT > "$T/check" 2>&1
    check "interrupted: the spectral file checks" test $? -eq 0
    spp=$(oiiotool --info -v "$T/i.spectral.exr" | awk '/samplesPerPixel:/ { print $2 }')
    check "interrupted: fewer samples than asked ($spp)" test "${spp:-0}" -gt 0 -a "${spp:-0}" -lt 100000
else
    kill $pid 2> /dev/null
    wait $pid
    bad "interrupted: the render never finished a pass"
fi

finish
