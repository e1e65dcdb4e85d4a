#!/usr/bin/env bash
# Spectral images out (-o NAME.spectral.exr): each spectral mode on the
# OpenCL backend (cli_spectral_cpu.sh: the CPU reference) writes a file that tests/spectral_check.cpp reads back with
# OpenImageIO and checks against independent computations: its integral with
# the CIE 1931 CMFs against the XYZ film of the same render (the .exr written
# beside it), a pixel that sees the F11 lamp of tests/data/scenes/lamp_wall.scene
# against the lamp's spectrum at luminance 1000; rgb and unsupported bin
# widths are refused before rendering, so is a spectral film too large for
# this machine's memory; an interrupted render writes a valid spectral file
# of the passes done; and (when colour-science and OpenImageIO's Python
# module are there) colour.read_spectral_image_Fichet2021 reads it.
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
# 4096x4096 at 1 nm: a film of 400 doubles a pixel is 54 GB alone.
mem_kb=$(awk '/^MemTotal:/ { print $2 }' /proc/meminfo)
if [ "$mem_kb" -lt $((50 * 1024 * 1024)) ]; then
    refused "4096x4096 at 1 nm" "needs .* GB of host memory" --mode truth --spectral-nm 1 \
        --width 4096 --height 4096 -o "$T/r.spectral.exr" --backend cpu
    refused "4096x4096 at 1 nm, OpenCL" "needs .* GB of host memory" --mode truth \
        --spectral-nm 1 --width 4096 --height 4096 -o "$T/r.spectral.exr"
else
    echo "  skipped the memory refusal: this machine has $((mem_kb / 1024 / 1024)) GB"
fi
# 5 nm at the largest image of 2 spp fits in a few GB less than 1 nm: the
# refusal is not of every large image.
grep -q "4096x4096 spectral image of 400 bins needs" "$T/err" 2> /dev/null ||
    [ "$mem_kb" -ge $((50 * 1024 * 1024)) ] || bad "the refusal names the image and bins"

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

# colour-science's reader, when it and OpenImageIO's Python module are there.
if "$PY" -c "import colour, OpenImageIO" 2> /dev/null; then
    for f in ref ml truth truth1 mlc hero; do
        f=$f-opencl
        "$PY" - "$T/$f.spectral.exr" "$T/$f.exr" << 'PYEOF' > "$T/py" 2>&1
import sys, warnings
warnings.filterwarnings("ignore")
import numpy as np, colour, OpenImageIO as oiio
comp, spec = colour.read_spectral_image_Fichet2021(sys.argv[1], additional_data=True)
wl, val = comp["S0"]
assert spec.is_emissive, "not emissive"
n = len(wl)
assert n in (80, 400), n
step = 400 / n
assert np.allclose(wl, 380 + step * (np.arange(n) + 0.5)), wl[:3]
# the values are the file's: compare with the S0 channels read directly
inp = oiio.ImageInput.open(sys.argv[1])
names = list(inp.spec().channelnames)
px = inp.read_image("float")
for i in (0, n // 2, n - 1):
    name = "S0.%snm" % (("%g" % wl[i]).replace(".", ","))
    c = names.index(name)
    assert np.allclose(val[..., i], px[..., c]), name
print("colour %s reads %s: %d bins, %s" % (colour.__version__, sys.argv[1].split("/")[-1], n,
      val.shape))
PYEOF
        rc=$?
        cat "$T/py" | sed 's/^/  /'
        check "colour-science reads $f" test $rc -eq 0
    done
else
    echo "  skipped colour-science's reader: $PY has no colour (pip install colour-science OpenImageIO)"
fi
finish
