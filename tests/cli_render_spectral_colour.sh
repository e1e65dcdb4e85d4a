#!/usr/bin/env bash
# colour-science (colour.read_spectral_image_Fichet2021) reads the spectral
# EXR files of every spectral mode: emissive, 80 or 400 bins at the bin
# centres, and the values those of the file's own S0 channels read with
# OpenImageIO. tools/setup.sh installs colour-science and OpenImageIO's
# Python module from PyPI into a virtual environment beside the build
# (build/pyenv); SPECMIP_PYTHON names another interpreter.
source "$(dirname "$0")/lib_cli.sh"
source "$(dirname "$0")/lib_spectral.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
check "colour-science and OpenImageIO importable by $PY (tools/setup.sh)" \
    "$PY" -c "import colour, OpenImageIO"
for m in ref ml truth truth1 mlc hero; do
    nm=()
    [ $m = truth1 ] && nm=(--spectral-nm 1)
    "$BIN" render "$SCENE" --quiet --mode "${m%1}" "${nm[@]}" -o "$T/$m.spectral.exr" 2> "$T/err"
    rc=$?
    check "$m: render exit 0 (got $rc: $(tail -1 "$T/err"))" test $rc -eq 0 -a -s "$T/$m.spectral.exr"
    "$PY" - "$T/$m.spectral.exr" << 'PYEOF' > "$T/py" 2>&1
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
assert np.any(px > 0), "an all-black file"
for i in (0, n // 2, n - 1):
    name = "S0.%snm" % (("%g" % wl[i]).replace(".", ","))
    c = names.index(name)
    assert np.allclose(val[..., i], px[..., c]), name
print("colour %s reads %s: %d bins, %s" % (colour.__version__, sys.argv[1].split("/")[-1], n,
      val.shape))
PYEOF
    rc=$?
    sed 's/^/  /' "$T/py"
    check "colour-science reads $m" test $rc -eq 0
done
finish
