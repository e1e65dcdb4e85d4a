#!/bin/bash
# --white: a chromatic adaptation (Bradford) of the image from the chosen
# white to the display's D65. Closed form: a room of constant reflectance lit
# by illuminant A reflects light of A's spectrum alone, so with --white A it
# is neutral exactly as far as a room lit by D65 is (the CIE D65 spectrum's
# chromaticity is 1e-4 from the sRGB white: both renders measured at r/g
# 0.99993, b/g 0.99969 in truth mode). auto finds A as the brightest emitter;
# D65 changes nothing; the spectral EXR stays as rendered; the white is in
# the EXR's metadata; a bad value is exit 2. The CPU reference: no device.
source "$(dirname "$0")/lib_cli.sh"

room() {
    cat <<S
image 16 16
camera position 0 0 -4 direction 0 0 1 fov 60
spectrum lamp file $1
spectrum grey equal
material wall reflect grey 0.8
material lamp reflect grey 0.8 emit lamp 10
quad lamp -1 2 -1  1 2 -1  1 2 1  -1 2 1
quad wall -3 -1 -3  -3 -1 3  3 -1 3  3 -1 -3
quad wall -3 -1 3  -3 3 3  3 3 3  3 -1 3
S
}
room illuminant_A.csv > "$T/a.scene"
room illuminant_D65_1nm.csv > "$T/d65.scene"
R=(--backend cpu --mode truth --spp 8 --seed 5 --quiet)
# avg FILE: the image's mean R G B
avg() { oiiotool --stats "$1" 2>/dev/null | awk '/Stats Avg/ { print $3, $4, $5 }'; }
render() { "$BIN" render "$@" "${R[@]}" || bad "render $*"; }

render "$T/a.scene" -o "$T/plain.exr"
render "$T/a.scene" -o "$T/A.exr" --white A
render "$T/a.scene" -o "$T/auto.exr" --white auto
render "$T/a.scene" -o "$T/D65.exr" --white D65
render "$T/d65.scene" -o "$T/daylight.exr"
read -r r g b <<< "$(avg "$T/plain.exr")"
check "unbalanced: warm (r/b $r/$b)" num "$(awk -v r="$r" -v b="$b" 'BEGIN { print r / b }')" '>' 3
read -r r g b <<< "$(avg "$T/A.exr")"
read -r dr dg db <<< "$(avg "$T/daylight.exr")"
check "--white A: r/g $r/$g near 1" near "$(awk -v a="$r" -v b="$g" 'BEGIN { print a / b }')" 1 5e-4
check "--white A: b/g $b/$g near 1" near "$(awk -v a="$b" -v b="$g" 'BEGIN { print a / b }')" 1 5e-4
check "--white A: r/g as neutral as D65 light ($dr/$dg)" \
    near "$(awk -v a="$r" -v b="$g" -v c="$dr" -v d="$dg" 'BEGIN { print a / b - c / d }')" 0 1e-5
check "--white A: b/g as neutral as D65 light ($db/$dg)" \
    near "$(awk -v a="$b" -v b="$g" -v c="$db" -v d="$dg" 'BEGIN { print a / b - c / d }')" 0 1e-5
check "auto: A's pixels" same_pixels "$T/auto.exr" "$T/A.exr"
# a room lit by a point light of A beside a weaker area light of D65: auto
# weighs the point light by its power (lights.h spm_light_power) and finds A
{ room illuminant_D65_1nm.csv | sed 's/emit lamp 10/emit lamp 0.5/'
  echo "spectrum lampA file illuminant_A.csv"
  echo "light point 0 1 0 lampA 200"; } > "$T/point.scene"
render "$T/point.scene" -o "$T/point-auto.exr" --white auto
render "$T/point.scene" -o "$T/point-A.exr" --white A
check "auto with a point light: A's pixels" same_pixels "$T/point-auto.exr" "$T/point-A.exr"
check "D65: unchanged" same_pixels "$T/D65.exr" "$T/plain.exr"
check "the white in the metadata" eval \
    "oiiotool --info -v '$T/A.exr' | grep -q 'specmip:white: \"A (Bradford to D65)\"'"
render "$T/a.scene" -o "$T/s1.spectral.exr"
render "$T/a.scene" -o "$T/s2.spectral.exr" --white A
check "the spectral EXR stays as rendered" same_pixels "$T/s1.spectral.exr" "$T/s2.spectral.exr"
for w in nonsense "$T/none.csv"; do
    "$BIN" render "$T/a.scene" "${R[@]}" -o "$T/bad.exr" --white "$w" 2> "$T/err"
    [ $? -eq 2 ] && grep -qF -- "--white $w" "$T/err" && [ ! -e "$T/bad.exr" ] && ok ||
        bad "--white $w: not refused: $(cat "$T/err")"
done
finish
