#!/usr/bin/env bash
# A textured quad under a uniform D65 sky shows its texture: an 8-bit sRGB
# PNG of 4 x 4 blocks of 16 colours (written here), on a Lambertian quad
# that fills an orthographic view, lit by a background of luminance 1 from
# every direction, so each point's radiance is its reflectance times the
# sky's and a block's linear sRGB is the decoded texel's. Per block (its
# middle half, away from the bilinear seams) the mean colour is within
# CIEDE2000 1 of the texel, in every mode on both backends (white Y = 1).
# The block means converge as 1 / sqrt(spp): at 512 spp the worst block is
# 0.62 off in truth, 0.70 in ml, 0.62 in hero (measured, seed 5; 0.53-0.99
# over seeds 5-7), mostly the continuation to the sky on the darkest texels,
# whose paths Russian roulette ends more often (spm_shared.h
# SPM_TEX_SURVIVE_MIN), and the grid's random corners; the lift's own error
# under 0.01. colour-science and OpenImageIO's Python module come from
# tools/setup.sh (build/pyenv); SPECMIP_PYTHON names another interpreter.
source "$(dirname "$0")/lib_cli.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
check "colour-science and OpenImageIO importable by $PY (tools/setup.sh)" \
    "$PY" -c "import colour, OpenImageIO"

"$PY" "$ROOT/tests/texture_blocks.py" write "$T/blocks.png" || bad "no texture written"
cat > "$T/quad.scene" <<'SCENE'
image 32 32
spp 512
camera position 0 0 -2  direction 0 0 1  orthographic 2
spectrum d65 file illuminant_D65.csv
texture blocks blocks.png
material board reflect texture blocks
quad board  -1 -1 0  1 -1 0  1 1 0  -1 1 0
background both d65 1
SCENE
for backend in opencl cpu; do
  for mode in truth ref ml mlc hero rgb; do
    "$BIN" render "$T/quad.scene" --backend $backend --mode $mode --seed 5 --quiet \
      -o "$T/$backend-$mode.exr" 2>"$T/err" || { bad "$backend $mode: $(cat "$T/err")"; continue; }
    "$PY" "$ROOT/tests/texture_blocks.py" "$T/blocks.png" "$T/$backend-$mode.exr" > "$T/py" 2>&1
    rc=$?
    check "$backend $mode: every block within dE00 1 of its texel: $(cat "$T/py")" test $rc -eq 0
    echo "$backend $mode $(tail -1 "$T/py")"
  done
done
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
