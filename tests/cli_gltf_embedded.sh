#!/usr/bin/env bash
# Images embedded in a glTF read as image files beside it are: models of
# tools/make_textured_gltf.py with every map — maps.gltf (a base colour with
# alpha under alphaMode MASK, a metallic-roughness map, a normal map),
# blocks_lamp.gltf (an emissive map) and board_mr.gltf with its base colour
# as a JPEG (the PNG re-encoded by oiiotool) — each packed by
# tools/gltf_embed.py as a GLB (images in bufferViews) and as a .gltf of
# data: URIs, must render pixel for pixel as the model with external files
# (the same bytes through the same decoder, pyramid and coefficient table),
# on both backends, with no warning that a map was not applied or replaced
# by its mean colour. Renders of 16 x 16 pixels at 4 spp: identity needs no
# more.
source "$(dirname "$0")/lib_cli.sh"
python3 "$ROOT/tools/make_textured_gltf.py" "$T" || bad "no model written"
oiiotool "$T/board_base.png" -o "$T/board_base.jpg" || bad "no JPEG written"
sed 's/board_base\.png/board_base.jpg/' "$T/board_mr.gltf" > "$T/board_jpg.gltf"
check "the JPEG model names the JPEG" grep -q 'board_base.jpg' "$T/board_jpg.gltf"
for m in maps blocks_lamp board_jpg; do
  python3 "$ROOT/tools/gltf_embed.py" "$T/$m.gltf" "$T/${m}_glb.glb" || bad "$m: no GLB"
  python3 "$ROOT/tools/gltf_embed.py" "$T/$m.gltf" "$T/${m}_data.gltf" || bad "$m: no data: URIs"
done
check "the GLB's images are bufferViews" grep -aq '"mimeType":"image/png","bufferView"' "$T/maps_glb.glb"
check "the data: model's images are data: URIs" grep -q 'data:image/jpeg;base64,' "$T/board_jpg_data.gltf"
render() {  # render MODEL-FILE BACKEND MODE OUT
  printf 'image 16 16\nspp 4\ncamera position 0 0 -2  direction 0 0 1  orthographic 2
spectrum d65 file illuminant_D65.csv\nbackground both d65 1\nmesh %s\n' "$1" > "$T/$4.scene"
  "$BIN" render "$T/$4.scene" --backend "$2" --mode "$3" --seed 5 -o "$T/$4.exr" \
    > /dev/null 2> "$T/$4.err" || bad "$4: $(cat "$T/$4.err")"
}
for backend in cpu opencl; do
  mode=truth; [ $backend = opencl ] && mode=ml
  for m in maps blocks_lamp board_jpg; do
    render "$m.gltf" $backend $mode "$m-$backend"
    for form in glb.glb data.gltf; do
      out="$m-${form%%.*}-$backend"
      render "${m}_$form" $backend $mode "$out"
      check "$out: no map left out: $(cat "$T/$out.err")" \
        bash -c "! grep -Eq 'embedded|not applied|cannot be read|replaced by its mean' '$T/$out.err'"
      check "$out: the pixels of the model with image files" \
        same_pixels "$T/$m-$backend.exr" "$T/$out.exr"
    done
  done
done
finish
