#!/usr/bin/env bash
# A receding checkerboard at 1 spp: aliasing gone, mean right. A level camera
# at height 1 over a ground plane of 0.1-wide squares of linear grey 0.8 and
# 0.05 (mean 0.425), lit from straight above by a distant light of E = pi,
# so a pixel's value is the reflectance the texture lookup picked (next-event
# estimation at the first vertex, no roulette in it; nothing else lights the
# plane). tests/texture_recede.py splits the image by the closed-form
# footprint h / r of row r below the horizon:
#   far rows (a pixel at least one square across, dozens along the view):
#     the mean within 0.01 of 0.425, the pixels' RMS deviation from it under
#     0.05 and the 4 x 4 blocks' under 0.015 (measured, seed 3: 0.4248, 0.024
#     and 0.0055 on both backends, the colour grid's noise; with the mip
#     level held at 0: 0.435, 0.376 and 0.095, one square's colour a pixel);
#   near rows (a pixel a quarter of a square or less): the board still
#     sharp, the pixels' spread over half the contrast above 0.5 (measured
#     0.72; with the level held at the coarsest: 0.06).
# colour-science's and OpenImageIO's Python from tools/setup.sh (build/pyenv);
# SPECMIP_PYTHON names another interpreter.
source "$(dirname "$0")/lib_cli.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
check "numpy and OpenImageIO importable by $PY (tools/setup.sh)" \
    "$PY" -c "import numpy, OpenImageIO"

cat > "$T/recede.scene" <<'SCENE'
image 256 128
spp 1
camera position 0 1 0  direction 0 0 1  fov 40
spectrum d65 file illuminant_D65.csv
texture board checker 8  0.8 0.8 0.8  0.05 0.05 0.05
material board reflect texture board
quad board  -2000 0 0  2000 0 0  2000 0 2000  -2000 0 2000  uv 0 0 5000 0 5000 2500 0 2500
light distant 0 -1 0 d65 3.14159265
SCENE
for backend in opencl cpu; do
  "$BIN" render "$T/recede.scene" --backend $backend --mode truth --seed 3 --quiet \
    -o "$T/$backend.exr" 2>"$T/err" || { bad "$backend: $(cat "$T/err")"; continue; }
  "$PY" "$ROOT/tests/texture_recede.py" "$T/$backend.exr" 0.1 0.425 0.75 > "$T/py" 2>&1 ||
    { bad "$backend: $(cat "$T/py")"; continue; }
  echo "$backend:" $(cat "$T/py")
  get() { awk -v k="$1" '$1 == k { print $2 }' "$T/py"; }
  check "$backend: far rows' mean $(get far_mean) within 0.01 of 0.425" near "$(get far_mean)" 0.425 0.01
  check "$backend: far pixels' RMS $(get far_pixel_rms) < 0.05" num "$(get far_pixel_rms)" '<' 0.05
  check "$backend: far blocks' RMS $(get far_block_rms) < 0.015" num "$(get far_block_rms)" '<' 0.015
  check "$backend: near rows sharp, $(get near_contrast) > 0.5" num "$(get near_contrast)" '>' 0.5
done
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
