#!/usr/bin/env bash
# A glTF model with a base-colour texture and an emissive texture, written by
# tools/make_textured_gltf.py: a board of 4 x 4 colour blocks (an 8-bit sRGB
# PNG) whose material maps to a coated one (metallic 0, roughness 0.5: alpha
# 0.25, index 1.5), textured per point, and a lamp panel behind it, facing
# away, with an emissive texture. Under a uniform D65 sky and an orthographic
# view that the board fills, each block (its middle half) must match the same
# block of the peer model, 16 untextured squares each of its block's decoded
# colour as its base colour (the mean-colour path the textured one replaces),
# rendered at 1024 spp: within CIEDE2000 3 in every mode on both backends at
# 256 spp (measured worst 1.1-2.0 over seeds 5-8, truth and hero on the CPU,
# against 1.2-2.4 for the peer itself at 256 spp: the noise of the only light,
# the sky, reached through the coated lobes and Russian roulette; a board
# rendered in its mean colour is off by more than 10 in most blocks). The
# lamp's emissive texture is textured per point (tests/cli_emit_texture.sh):
# no warning names it. colour-science and OpenImageIO's Python module:
# tools/setup.sh (build/pyenv); SPECMIP_PYTHON names another interpreter.
source "$(dirname "$0")/lib_cli.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
check "colour-science and OpenImageIO importable by $PY (tools/setup.sh)" \
    "$PY" -c "import colour, OpenImageIO"

python3 "$ROOT/tools/make_textured_gltf.py" "$T" || bad "no model written"
scene() {  # scene MODEL SPP
  printf 'image 32 32\nspp %s\ncamera position 0 0 -2  direction 0 0 1  orthographic 2
spectrum d65 file illuminant_D65.csv\nbackground both d65 1\nmesh %s\n' "$2" "$1"
}
scene board_peer.gltf 1024 > "$T/peer.scene"
scene board.gltf 256 > "$T/board.scene"
"$BIN" render "$T/peer.scene" --backend cpu --mode truth --seed 5 --quiet -o "$T/peer.exr" \
  2>"$T/err" || bad "the peer: $(cat "$T/err")"
for backend in opencl cpu; do
  for mode in truth ref ml mlc hero rgb; do
    "$BIN" render "$T/board.scene" --backend $backend --mode $mode --seed 5 \
      -o "$T/$backend-$mode.exr" > /dev/null 2>"$T/err" ||
      { bad "$backend $mode: $(cat "$T/err")"; continue; }
    check "$backend $mode: no mean-colour warning: $(cat "$T/err")" \
      bash -c "! grep -q 'mean colour' '$T/err'"
    check "$backend $mode: no emissive texture warned about: $(cat "$T/err")" \
      bash -c "! grep -q 'emissive' '$T/err'"
    "$PY" "$ROOT/tests/texture_blocks.py" pair "$T/peer.exr" "$T/$backend-$mode.exr" 3 > "$T/py" 2>&1
    rc=$?
    check "$backend $mode: every block within dE00 3 of the peer's: $(tail -3 "$T/py")" \
      test $rc -eq 0
    echo "$backend $mode $(tail -1 "$T/py")"
  done
done
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
