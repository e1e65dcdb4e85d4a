#!/usr/bin/env bash
# pbrt-v4 files from the command line (docs/PBRT.md): every malformed file of
# the bad-input corpus (tests/bad-inputs/pbrt_*.pbrt) exits 2 naming
# file:line:col and writes nothing; what is not rendered is warned about once
# per kind with a count of repeats, and --strict makes it an error; a
# published scene (Bitterli's CC0 Cornell box, tests/data/pbrt) renders from
# its own file within a measured bound of its Tungsten reference.
source "$(dirname "$0")/lib_cli.sh"
BAD=$ROOT/tests/bad-inputs

# file and what its message must say (after "file:line:col: ")
cases=(
  "pbrt_unterminated_string.pbrt:2:8:unterminated string"
  "pbrt_unterminated_bracket.pbrt:3:14:unterminated '['"
  "pbrt_wrong_param_type.pbrt:1:22:cannot be of type 'string'"
  "pbrt_shape_param_type.pbrt:2:22:cannot be of type 'rgb'"
  "pbrt_unknown_param_type.pbrt:2:20:unknown parameter type 'colour'"
  "pbrt_unknown_directive.pbrt:2:1:unknown directive 'Shapes'"
  "pbrt_unknown_material.pbrt:2:1:unknown material type \"plastic\""
  "pbrt_include_cycle.pbrt:3:9:include cycle"
  "pbrt_include_missing.pbrt:2:9:not found"
  "pbrt_include_outside.pbrt:2:9:leads outside the scene's folder"
  "pbrt_plymesh_outside.pbrt:2:17:leads outside the scene's folder"
  "pbrt_spectrum_outside.pbrt:2:20:leads outside the scene's folder"
  "pbrt_attribute_end.pbrt:4:1:AttributeEnd without AttributeBegin"
  "pbrt_bad_number.pbrt:2:15:found 'x'"
  "pbrt_named_missing.pbrt:2:1:no MakeNamedMaterial defines it"
  "pbrt_indices_count.pbrt:2:55:not a multiple of 3"
  "pbrt_distant_no_direction.pbrt:2:1:'from' and 'to' give no direction"
)
n=0
for c in "${cases[@]}"; do
  IFS=: read -r file line col want <<< "$c"
  msg=$("$BIN" render "$BAD/$file" -o "$T/bad.png" 2>&1); rc=$?
  check "$file: exit 2 (got $rc: $msg)" [ "$rc" -eq 2 ]
  check "$file: names $file:$line:$col and says '$want' (got: $msg)" \
    grep -qF -- "$file:$line:$col: " <<< "$msg"
  check "$file: says '$want' (got: $msg)" grep -qF -- "$want" <<< "$msg"
  check "$file: nothing written" [ ! -e "$T/bad.png" ]
  n=$((n + 1))
done
check "every pbrt file of the corpus has a case" \
  [ "$(ls "$BAD"/pbrt_*.pbrt | wc -l)" -eq "$n" ]

# Warnings: one per kind, the repeats counted; --strict: an error.
cat > "$T/warn.pbrt" <<'PBRT'
Film "rgb" "integer xresolution" 16 "integer yresolution" 16
Camera "spherical"
WorldBegin
LightSource "goniometric" "rgb I" [1 1 1]
LightSource "goniometric" "rgb I" [2 2 2]
LightSource "goniometric" "rgb I" [3 3 3]
Texture "checks" "spectrum" "checkerboard"
Material "diffuse" "texture reflectance" "checks"
AttributeBegin
AreaLightSource "diffuse" "rgb L" [4 4 4] "float power" 10
Translate 0 0 5
Shape "trianglemesh" "point3 P" [-1 -1 0 1 -1 0 0 1 0] "integer indices" [0 2 1]
AttributeEnd
LightSource "infinite" "string filename" "sky.exr"
PBRT
msg=$("$BIN" render "$T/warn.pbrt" --spp 1 -o "$T/warn.png" 2>&1); rc=$?
check "a scene with warnings renders (rc $rc: $msg)" [ "$rc" -eq 0 ]
check "its image written" [ -s "$T/warn.png" ]
check "LightSource \"goniometric\" warned once" \
  [ "$(grep -c 'LightSource "goniometric" ignored' <<< "$msg")" -eq 1 ]
check "at its first line" grep -qF 'warn.pbrt:4:1: LightSource "goniometric" ignored' <<< "$msg"
check "its repeats counted" \
  grep -qF 'warn.pbrt:4:1: LightSource "goniometric": ignored 3 times' <<< "$msg"
check "the reason said" grep -qF 'a light type specmip does not render' <<< "$msg"
check "an equal-area map named" \
  grep -qF "warn.pbrt:14:1: LightSource \"infinite\" with a 'filename' ignored" <<< "$msg"
check "the texture named" grep -qF 'warn.pbrt:7:1: Texture "checkerboard" ignored' <<< "$msg"
check "a texture's use named" \
  grep -qF "warn.pbrt:8:20: Material \"diffuse\": a texture as 'reflectance' ignored" <<< "$msg"
check "the camera named" grep -qF 'warn.pbrt:2:1: Camera "spherical"' <<< "$msg"
check "an unused parameter named" \
  grep -qF "warn.pbrt:10:43: AreaLightSource \"diffuse\": parameter 'float power' ignored" <<< "$msg"
msg=$("$BIN" render "$T/warn.pbrt" --spp 1 --strict -o "$T/strict.png" 2>&1); rc=$?
check "--strict: exit 2 (got $rc)" [ "$rc" -eq 2 ]
check "--strict: the first one named (got: $msg)" \
  grep -qF 'warn.pbrt:2:1: Camera "spherical"' <<< "$msg"
check "--strict: nothing written" [ ! -e "$T/strict.png" ]

# Bitterli's Cornell box from its own file against Tungsten's render (both
# 64 x 64). Measured: mean CIEDE2000 0.74, 0.74, 0.76 at 256 spp (seeds 1-3),
# 0.71 at 1024 (the floor: the reference resized from 1024 x 1024, its
# Gaussian filter); luminance ratio 0.992. Bounds: 1.0 and 2%.
CB=$ROOT/tests/data/pbrt/cornell-box
"$BIN" render "$CB/scene-v4.pbrt" --spp 256 --quiet -o "$T/cb.exr" 2> "$T/cb.err"; rc=$?
check "the Cornell box renders (rc $rc: $(cat "$T/cb.err"))" [ "$rc" -eq 0 ]
"$BIN" compare "$CB/tungsten_64.exr" "$T/cb.exr" --json > "$T/cmp.json"
de=$(jnum "$T/cmp.json" .mean)
check "mean CIEDE2000 against Tungsten $de < 1.0" num "$de" "<" 1.0
y() { oiiotool --stats "$1" 2>/dev/null | awk '/Stats Avg/ { print 0.2126 * $3 + 0.7152 * $4 + 0.0722 * $5 }'; }
ya=$(y "$CB/tungsten_64.exr"); yb=$(y "$T/cb.exr")
ratio=$(awk -v a="$ya" -v b="$yb" 'BEGIN { if (a > 0) printf "%.4f", b / a }')
check "luminance ratio $ratio within 2%" near "$ratio" 1 0.02
# LightSource "point", "distant" and a constant "infinite" over a diffuse
# plane of rho 0.5, seen from (0, 6, 0) with a 60 degree fov (64 x 64):
# - point: a blackbody I (normalised to luminance 1 by pbrt-v4) with power
#   40 pi, so I = 10 W/sr, at `from` (0, 1, 0) under Translate 0 1 0, so d = 2:
#   L = rho I cos(theta) / (pi d^2) = 0.3979 at its foot, times 0.997 (the
#   mean of cos^3 over the 2 x 2 centre pixels, as cli_mitsuba.sh);
# - distant: from (0 0 0) to (1 -2 0), illuminance 3: rho E cos / pi with
#   cos = 2 / sqrt(5) = 0.4270 everywhere;
# - infinite: L = 2 (illuminance 2 pi): rho L = 1 everywhere (the plane sees
#   the sky's upper half only).
# Measured ratios 0.9999, 0.9998 and 0.9976 on both backends; bound 1 %.
plane='Material "diffuse" "rgb reflectance" [0.5 0.5 0.5]
Shape "trianglemesh" "point3 P" [-5 0 -5 5 0 -5 5 0 5 -5 0 5] "integer indices" [0 1 2 0 2 3]'
head='Film "rgb" "integer xresolution" 64 "integer yresolution" 64
LookAt 0 6 0  0 0 0  0 0 1
Camera "perspective" "float fov" 60
WorldBegin'
printf '%s\n%s\n%s\n' "$head" 'AttributeBegin
Translate 0 1 0
LightSource "point" "blackbody I" 3000 "float power" 125.6637 "point3 from" [0 1 0]
AttributeEnd' "$plane" > "$T/point.pbrt"
printf '%s\n%s\n%s\n' "$head" \
  'LightSource "distant" "point3 from" [0 0 0] "point3 to" [1 -2 0] "float illuminance" 3' \
  "$plane" > "$T/distant.pbrt"
printf '%s\n%s\n%s\n' "$head" 'LightSource "infinite" "rgb L" [1 1 1] "float illuminance" 6.283185' \
  "$plane" > "$T/sky.pbrt"
ypx() { # image, x, y, w, h -> mean Y
    oiiotool "$1" --cut "$4x$5+$2+$3" --printstats 2>/dev/null |
        awk '/Stats Avg/ { print 0.2126 * $3 + 0.7152 * $4 + 0.0722 * $5 }'
}
for backend in cpu opencl; do
    for l in point distant sky; do
        "$BIN" render "$T/$l.pbrt" --spp 16 --quiet --backend $backend -o "$T/$l.exr" 2> "$T/$l.err"
        check "$backend: the $l light renders ($(cat "$T/$l.err"))" [ -s "$T/$l.exr" ]
        check "$backend: the $l light without warnings" [ ! -s "$T/$l.err" ]
    done
    r1=$(awk -v y="$(ypx "$T/point.exr" 31 31 2 2)" 'BEGIN { printf "%.4f", y / (0.5 * 10 / (3.14159265 * 4) * 0.997) }')
    r2=$(awk -v y="$(ypx "$T/distant.exr" 0 0 64 64)" 'BEGIN { printf "%.4f", y / (0.5 * 3 * 2 / sqrt(5) / 3.14159265) }')
    r3=$(awk -v y="$(ypx "$T/sky.exr" 0 0 64 64)" 'BEGIN { printf "%.4f", y / (0.5 * 2) }')
    check "$backend: the point light's foot against rho I / (pi d^2): ratio $r1 within 1%" near "$r1" 1 0.01
    check "$backend: the distant light against rho E cos / pi: ratio $r2 within 1%" near "$r2" 1 0.01
    check "$backend: the constant infinite light against rho L: ratio $r3 within 1%" near "$r3" 1 0.01
    echo "$backend: point foot ratio $r1, distant $r2, infinite $r3"
    rm -f "$T"/point.exr "$T"/distant.exr "$T"/sky.exr
done
finish
