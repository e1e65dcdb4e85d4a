#!/usr/bin/env bash
# KHR_texture_transform (spm_shared.h SPM_TEX_UVX), on the boards
# tools/make_textured_gltf.py writes: board_uvx.gltf reads its base colour
# and metallic-roughness maps through offset (0.5, 0.25) and scale (2, 1),
# board_uvr.gltf through a quarter turn too; their peers have no transform,
# their images the same maps transformed on disk (64 x 32: the scale's area
# 2 makes the footprint the same number of texels). The same seed on all:
# 1. board_uvx against its peer, within mean dE00 0.05 on both backends (the
#    same paths: measured 0 to 1e-3, a float's rounding in u' moving a texel
#    pick now and then), while the same board untransformed (board_mr.gltf)
#    is far from the peer (measured 25);
# 2. board_uvr against its peer within mean dE00 2 (measured 1.16 at 16
#    spp: the turn swaps the axes, so each texel pick reads the other
#    axis's random number and the blocks' edges carry different noise; a
#    turn the other way mirrors the board, measured 25);
# 3. the kernel against the CPU reference on board_uvx, within dE00 0.01 at
#    every pixel; no warning about texture transforms.
source "$(dirname "$0")/lib_cli.sh"
python3 "$ROOT/tools/make_textured_gltf.py" "$T" || bad "no model written"
dE() {  # dE A B: the mean and the max CIEDE2000 (compare's 5-pixel blur)
  "$BIN" compare "$1" "$2" --json |
    python3 -c 'import json, sys; r = json.load(sys.stdin); print(r["mean"], r["max"])'
}
render() {  # render MODEL BACKEND
  printf 'image 32 32\nspp 16\ncamera position 0 0 -2  direction 0 0 1  orthographic 2
spectrum d65 file illuminant_D65.csv\nbackground both d65 1\nmesh %s.gltf\n' "$1" > "$T/$1.scene"
  "$BIN" render "$T/$1.scene" --backend $2 --mode rgb --seed 3 -o "$T/$1-$2.exr" \
    > /dev/null 2>"$T/err" || { bad "$1 $2: $(cat "$T/err")"; return; }
  check "$1 $2: no texture transform warning: $(cat "$T/err")" \
    bash -c "! grep -qi 'texture transform' '$T/err'"
}
within() {  # within A B OP LIMIT WHAT
  read -r mean max < <(dE "$T/$1.exr" "$T/$2.exr")
  echo "$5: mean dE00 $mean, max $max"
  check "$5: mean dE00 $mean $3 $4" python3 -c "import sys; sys.exit(not $mean $3 $4)"
}
for b in opencl cpu; do
  for m in board_uvx board_uvx_peer; do render $m $b; done
  within board_uvx_peer-$b board_uvx-$b "<=" 0.05 "$b: transformed against transformed on disk"
done
for m in board_mr board_uvr board_uvr_peer; do render $m opencl; done
within board_uvx_peer-opencl board_mr-opencl ">=" 5 "the board without its transform"
within board_uvr_peer-opencl board_uvr-opencl "<=" 2 "a quarter turn against it on disk"
read -r mean max < <(dE "$T/board_uvx-cpu.exr" "$T/board_uvx-opencl.exr")
echo "kernel against the CPU reference: mean dE00 $mean, max $max"
check "the kernel against the CPU reference: max dE00 $max <= 0.01" \
  python3 -c "import sys; sys.exit(not $max <= 0.01)"
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
