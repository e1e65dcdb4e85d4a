#!/bin/bash
# 'texture NAME FILE|checker ...' and 'reflect texture NAME' (scene_texture.h):
# a Lambertian reflectance and an emission are textured per point (the
# per-block colours: cli_texture_quad.sh, cli_emit_texture.sh); other uses are
# the texture's mean colour, with a warning that says so. A floor under a checker texture of greys 0.25 and
# 0.75, and under an image of the same squares, renders other pixels than a
# floor of the constant 0.5, with the same mean: within 3 % (the three seeds
# 3, 4, 5 measured 0.2 %, 1.4 %, 0.3 %; the flat floor's own mean moves 3.5 %
# from seed to seed at 16 spp); a texture on an emission is rendered per point;
# a texture that is never used is warned about; bad statements are exit 2
# naming file and line; an image outside the scene's folder is refused by
# the path rule.
# usage: bash tests/cli_texture.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

scene() {  # scene FILE DEFINITIONS FLOOR_COLOUR [LAMP_EMISSION]
  cat > "$1" <<SCENE
image 16 12
spp 16
camera position 0 0.5 -3  direction 0 -0.1 1  fov 60
spectrum equal equal
$2
material floor reflect $3
material lamp  emit ${4:-equal 10}
quad floor  -2 0 -2  -2 0 2  2 0 2  2 0 -2
quad lamp   -0.5 1 0.5  -0.5 1 -0.5  0.5 1 -0.5  0.5 1 0.5
SCENE
}
oiiotool --pattern checker:width=2:height=2:color1=0.25,0.25,0.25:color2=0.75,0.75,0.75 8x8 3 \
  -d float -o "$T/check.exr" 2>/dev/null || bad "oiiotool made no test image"
mkdir -p "$T/out" && cp "$T/check.exr" "$T/out/"
scene "$T/flat.scene" "spectrum half inline 380 0.5 780 0.5 end" "half"
scene "$T/checker.scene" "texture c checker 4 0.25 0.25 0.25 0.75 0.75 0.75 wrap mirror" "texture c"
scene "$T/image.scene" "texture c check.exr wrap clamp scale 1" "texture c"
for s in flat checker image; do
  "$BIN" render "$T/$s.scene" --backend cpu --seed 4 --quiet -o "$T/$s.exr" 2>"$T/$s.err" ||
    bad "render of $s.scene: $(cat "$T/$s.err")"
done
hash() { oiiotool --hash "$1" 2>/dev/null | sed -n 's/.*SHA-1: *//p'; }
avg() { oiiotool "$1" --printstats 2>/dev/null | awk '/Stats Avg/ { print $3 }'; }
h=$(hash "$T/flat.exr") m=$(avg "$T/flat.exr")
[ -n "$h" ] && ok || bad "no image of the flat floor"
for s in checker image; do
  [ "$(hash "$T/$s.exr")" != "$h" ] && ok || bad "$s: the texture is rendered as its mean colour"
  a=$(avg "$T/$s.exr")
  num "$a" ">" 0 && near "$a" "$m" "$(awk -v m="$m" 'BEGIN { print 0.03 * m }')" && ok ||
    bad "$s: mean red $a, the flat floor's $m"
  grep -q "applied as its mean colour" "$T/$s.err" && bad "$s: warned as a mean: $(cat "$T/$s.err")" || ok
done
# an emission: textured per point (per block: cli_emit_texture.sh), not its
# mean: no warning, other pixels than a lamp of the mean (the floor's
# luminance within 15 % of that lamp's: seeds 3-6 measured -2 % to +6 %, the
# lamp's own seed-to-seed spread 13 %)
scene "$T/lamp.scene" "texture c check.exr" "equal 0.5" "texture c"
scene "$T/mean.scene" "" "equal 0.5" "equal 0.5"
lum() { oiiotool "$1" --printstats 2>/dev/null | awk '/Stats Avg/ { print 0.2126 * $3 + 0.7152 * $4 + 0.0722 * $5 }'; }
"$BIN" render "$T/mean.scene" --backend cpu --seed 4 --quiet -o "$T/mean.exr" 2>/dev/null ||
  bad "the mean lamp does not render"
"$BIN" render "$T/lamp.scene" --backend cpu --seed 4 --quiet -o "$T/lamp.exr" 2>"$T/err"
rc=$?
check "an emission texture renders (exit $rc) without a warning: $(cat "$T/err")" \
  test $rc -eq 0 -a ! -s "$T/err"
check "an emission texture is not its mean" test "$(hash "$T/lamp.exr")" != "$(hash "$T/mean.exr")"
ml=$(lum "$T/mean.exr") tl=$(lum "$T/lamp.exr")
check "an emission texture lights as its mean: luminance $tl, the mean lamp's $ml" \
  near "$tl" "$ml" "$(awk -v m="$ml" 'BEGIN { print 0.15 * m }')"

# unused: warned by name
scene "$T/unused.scene" "texture spare checker 2 0 0 0 1 1 1" "equal 0.5"
"$BIN" render "$T/unused.scene" --backend cpu --quiet -o "$T/u.exr" 2>"$T/err" &&
  grep -q "unused.scene:5:9: texture 'spare' is never used" "$T/err" && ok ||
  bad "an unused texture is not warned about: $(cat "$T/err")"

# errors: exit 2, file:line:col and the problem
refused() {  # refused WHAT DEFINITIONS FLOOR EXPECTED
  scene "$T/bad.scene" "$2" "$3"
  "$BIN" render "$T/bad.scene" --backend cpu --quiet -o "$T/bad.exr" 2>"$T/err"
  local rc=$?
  [ $rc -eq 2 ] && grep -qF -- "$4" "$T/err" && [ ! -e "$T/bad.exr" ] && ok ||
    bad "$1: exit $rc, $(cat "$T/err")"
}
refused "unknown texture" "" "texture nope" "bad.scene:6:32: unknown texture 'nope'"
refused "missing image" "texture c none.png" "texture c" "bad.scene:5:11: texture image 'none.png' not found"
refused "not an image" "texture c bad.scene" "texture c" "texture image 'bad.scene' cannot be read"
refused "bad wrap" "texture c check.exr wrap twist" "texture c" "bad.scene:5:26: expected 'repeat', 'clamp' or 'mirror'"
refused "twice" "texture c check.exr
texture c check.exr" "texture c" "bad.scene:6:9: texture 'c' is already defined"
refused "negative colour" "texture c checker 2 -1 0 0 1 1 1" "texture c" "bad.scene:5:21"
refused "outside the root" "texture c ../out/check.exr" "texture c" "--allow-path"
scene "$T/bad.scene" "texture c checker 2 0 0 0 1 1 1" "equal 0.5"
sed -i 's/^material floor reflect equal 0.5/material floor conductor texture c equal 1/' "$T/bad.scene"
"$BIN" render "$T/bad.scene" --backend cpu --quiet -o "$T/bad.exr" 2>"$T/err"
[ $? -eq 2 ] && grep -qF "a texture gives a reflectance or an emission, not an optical constant" "$T/err" &&
  ok || bad "a texture on a conductor's eta: $(cat "$T/err")"
finish
