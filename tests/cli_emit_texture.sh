#!/usr/bin/env bash
# A textured light seen directly shows its texture: the 4 x 4 blocks PNG of
# tests/cli_texture_quad.sh as the emission of a quad (`emit texture blocks
# 2.5`) that fills the view (a 2 x 2 quad 2 away, 2 atan(1/2) across), its front face toward the camera,
# nothing else in the scene. Each pixel's radiance is its texel's emission
# (lifted times D65, luminance the texel's) times 2.5, so per block (its
# middle half) the mean linear sRGB over 2.5 is within CIEDE2000 1 of the
# decoded texel, in every mode on both backends, and by the light tracer
# (--integrator light: the light's own vertex seen by the camera, its texel
# looked up at the subpath's start; 1024 subpaths a pixel, as each lands in a
# random pixel). The worst block at 128 spp, seed 5, is 0.39 off (truth,
# rgb), 0.57 (ml), 0.84 (hero); the light tracer's 0.65 (seed 5; 1.34 at 128
# subpaths a pixel), measured. The same quad facing
# away shows nothing (one-sided emission is kept).
# The same from a glTF (tools/make_textured_gltf.py blocks_lamp.gltf): the
# blocks image as the emissiveTexture of a panel facing the camera, times
# emissiveFactor (1 0.8 0.6) and KHR_materials_emissive_strength 2.5: per
# block within CIEDE2000 1 of the decoded texel times (2.5 2 1.5), in every
# mode on both backends at 64 spp (hero at 256), nothing warned.
# colour-science and OpenImageIO's Python module come from tools/setup.sh
# (build/pyenv).
source "$(dirname "$0")/lib_cli.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
check "colour-science and OpenImageIO importable by $PY (tools/setup.sh)" \
    "$PY" -c "import colour, OpenImageIO"

"$PY" "$ROOT/tests/texture_blocks.py" write "$T/blocks.png" || bad "no texture written"
scene() { # $1: spp, $2: the quad's corners and uv
  cat <<SCENE
image 32 32
spp $1
camera position 0 0 -2  direction 0 0 1  fov 53.1301024
texture blocks blocks.png
material lamp emit texture blocks 2.5
quad lamp $2
SCENE
}
scene 128 "-1 -1 0  -1 1 0  1 1 0  1 -1 0  uv 0 0  0 1  1 1  1 0" > "$T/quad.scene"
scene 16 "-1 -1 0  1 -1 0  1 1 0  -1 1 0" > "$T/back.scene"
blocks() { # $1: name, $2: image
  "$PY" "$ROOT/tests/texture_blocks.py" "$T/blocks.png" "$2" 2.5 > "$T/py" 2>&1
  local rc=$?
  check "$1: every block within dE00 1 of its texel x 2.5: $(cat "$T/py")" test $rc -eq 0
  echo "$1 $(tail -1 "$T/py")"
}
for backend in opencl cpu; do
  for mode in truth ref ml mlc hero rgb; do
    "$BIN" render "$T/quad.scene" --backend $backend --mode $mode --seed 5 --quiet \
      -o "$T/$backend-$mode.exr" 2>"$T/err" || { bad "$backend $mode: $(cat "$T/err")"; continue; }
    blocks "$backend $mode" "$T/$backend-$mode.exr"
  done
  "$BIN" render "$T/quad.scene" --backend $backend --mode ml --integrator light --seed 5 --spp 1024 --quiet \
    -o "$T/$backend-light.exr" 2>"$T/err" || { bad "$backend light: $(cat "$T/err")"; continue; }
  blocks "$backend ml, light tracer" "$T/$backend-light.exr"
done
python3 "$ROOT/tools/make_textured_gltf.py" "$T" || bad "no model written"
printf 'image 32 32\nspp 64\ncamera position 0 0 -2  direction 0 0 1  fov 53.1301024
mesh blocks_lamp.gltf\n' > "$T/lamp.scene"
for backend in opencl cpu; do
  for mode in truth ref ml mlc hero rgb; do
    spp=64; [ $mode = hero ] && spp=256
    "$BIN" render "$T/lamp.scene" --backend $backend --mode $mode --seed 5 --spp $spp \
      -o "$T/lamp-$backend-$mode.exr" > /dev/null 2>"$T/err" ||
      { bad "lamp $backend $mode: $(cat "$T/err")"; continue; }
    check "lamp $backend $mode: nothing warned: $(cat "$T/err")" bash -c "! grep -q warning '$T/err'"
    "$PY" "$ROOT/tests/texture_blocks.py" "$T/board_base.png" "$T/lamp-$backend-$mode.exr" \
      2.5,2,1.5 > "$T/py" 2>&1
    rc=$?
    check "lamp $backend $mode: every block within dE00 1 of texel x factor x strength: $(tail -3 "$T/py")" \
      test $rc -eq 0
    echo "lamp $backend $mode $(tail -1 "$T/py")"
  done
done
"$BIN" render "$T/back.scene" --backend cpu --mode rgb -o "$T/back.exr" 2>"$T/err" ||
  bad "back: $(cat "$T/err")"
grep -q "lights nothing the camera can see" "$T/err"
check "the quad facing away is warned about: $(cat "$T/err")" test $? -eq 0
"$PY" -c "import sys, OpenImageIO as o; sys.exit(int(o.ImageBuf(sys.argv[1]).get_pixels(o.FLOAT).max() != 0))" \
  "$T/back.exr"
check "the quad's back face emits nothing" test $? -eq 0
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
