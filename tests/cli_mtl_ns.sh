#!/usr/bin/env bash
# MTL's map_Ns (docs/SCENE_FORMAT.md: an exponent map, each texel t the
# exponent Ns t, read as the roughness of Walter et al.'s alpha =
# sqrt(2 / (Ns t + 2))): tools/make_textured_gltf.py's ns_board.obj, a coated
# grey plane whose map_Ns gives 16 blocks exponents 4 to 192, against
# ns_board.gltf, the same plane with that roughness as a glTF
# metallicRoughnessTexture, under a distant light along the view, so each
# block's highlight is its width's (1 / alpha^2 at the mirror direction).
# The two images, same seed, on both backends: mean dE00 within NS_TOL
# (measured below); the OBJ with its map ignored (Ns 200 throughout) is
# far outside it. No warning about the map; on a diffuse material (no
# specular lobe) the map is warned about by name.
source "$(dirname "$0")/lib_cli.sh"
# Measured (32 x 32, 64 spp, seed 3, both backends): mean dE00 0 (the same
# paths, the same parameters, the same one-byte roughness map); the glTF map
# one code rougher in every block: 0.49 (cpu), so one block rounded to its
# neighbouring code stays well inside; two seeds differ by 1.10; without
# the map 11.7.
NS_TOL=0.1

python3 "$ROOT/tools/make_textured_gltf.py" "$T" || bad "no model written"
scene() {  # scene MODEL
  printf 'image 32 32\nspp 64\ncamera position 0 0 -2  direction 0 0 1  orthographic 2
spectrum d65 file illuminant_D65.csv\nbackground both d65 0.2
light distant 0 0 1 d65 3\nmesh %s\n' "$1"
}
meandE() {  # meandE A B: the mean CIEDE2000 (compare's 5-pixel blur)
  "$BIN" compare "$1" "$2" --json |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["mean"])'
}
scene ns_board.obj > "$T/obj.scene"
scene ns_board.gltf > "$T/gltf.scene"
for backend in cpu opencl; do
  for model in obj gltf; do
    "$BIN" render "$T/$model.scene" --backend $backend --mode truth --seed 3 \
      -o "$T/$backend-$model.exr" > /dev/null 2>"$T/err" ||
      { bad "$model $backend: $(cat "$T/err")"; continue; }
    check "$model $backend: no warning: $(cat "$T/err")" \
      bash -c "! grep -q 'warning' '$T/err'"
  done
  de=$(meandE "$T/$backend-gltf.exr" "$T/$backend-obj.exr")
  echo "$backend: map_Ns against its glTF roughness map: mean dE00 $de"
  check "$backend: map_Ns as its roughness map: mean dE00 $de <= $NS_TOL" num "$de" '<=' $NS_TOL
done
# the same board without its map: the check above must see it
sed -i '/map_Ns/d' "$T/ns_board.mtl"
"$BIN" render "$T/obj.scene" --backend cpu --mode truth --seed 3 -o "$T/flat.exr" \
  > /dev/null 2>&1 || bad "the board without map_Ns does not render"
de=$(meandE "$T/cpu-gltf.exr" "$T/flat.exr")
echo "without map_Ns: mean dE00 $de"
check "without map_Ns the board differs: mean dE00 $de > 4 x $NS_TOL" \
  num "$de" '>' "$(awk -v t=$NS_TOL 'BEGIN { print 4 * t }')"
# on a diffuse material (Ks black) the map has no width to set: warned by name
sed -i 's/^Ks .*/Ks 0 0 0/; $a map_Ns ns_exponent.png' "$T/ns_board.mtl"
"$BIN" render "$T/obj.scene" --backend cpu --mode truth --seed 3 -o "$T/diffuse.exr" \
  > /dev/null 2>"$T/err" || bad "the diffuse board does not render: $(cat "$T/err")"
check "map_Ns on a diffuse material is warned about by name: $(cat "$T/err")" \
  grep -q "map_Ns 'ns_exponent.png' not applied" "$T/err"
echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
