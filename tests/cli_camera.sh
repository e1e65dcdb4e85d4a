#!/bin/bash
# The camera statement and the command line's camera, on both backends, by
# the light of one small square lamp on black (its image's centroid and
# spread, pixel statistics from oiiotool --dumpdata):
#  - a thin lens blurs the lamp into its circle of confusion, whose diameter
#    the thin-lens formula gives: on the plane at unit distance (the film,
#    tan_half wide per half image) it is c = D |1/F - 1/Z| for an aperture
#    of diameter D focused at F and a point at depth Z (the sensor's
#    A |S2 - S1| / S2 * f / (S1 - f) over its image distance S1 f / (S1 - f));
#    a uniform disk of diameter c has a variance of c^2 / 16 per axis;
#  - an orthographic view's lamp keeps its size at any distance;
#  - `fov ... vertical` spans the image's height; horizontal is the default;
#  - `up` rolls the view; `lookat` aims it;
#  - --look-from, --look-at and --fov render what the same camera written in
#    the scene renders, pixel for pixel; out-of-range values are errors.
# usage: bash tests/cli_camera.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

# lamp_scene FILE W H CAMERA... : a square lamp of half-size 0.5 centred at
# (LX, LY, LZ) (default 0 0 10) facing -z, seen by the camera clauses given.
lamp_scene() {
  local f=$1 w=$2 h=$3; shift 3
  local x=${LX:-0} y=${LY:-0} z=${LZ:-10} s=${LS:-0.5}
  cat > "$f" <<EOF
image $w $h
camera $*
spectrum equal equal
spectrum white file colorchecker_n_ohta.csv column white_9_5
material lamp reflect white emit equal 1
quad lamp  $(awk -v x=$x -v y=$y -v z=$z -v s=$s 'BEGIN {
  printf "%g %g %g  %g %g %g  %g %g %g  %g %g %g", x-s,y-s,z, x-s,y+s,z, x+s,y+s,z, x+s,y-s,z }')
EOF
}
# moments EXR: "cx cy vx vy sum": the centroid (pixels, x right, y down) and
# variance per axis of the image's R+G+B; "empty" when it is black.
moments() {
  oiiotool --dumpdata "$1" | awk '
    /^ *Pixel/ { gsub(/[(),:]/, " "); v = $4 + $5 + $6; x = $2 + 0.5; y = $3 + 0.5
                 s += v; sx += v * x; sy += v * y; sxx += v * x * x; syy += v * y * y }
    END { if (!(s > 0)) { print "empty"; exit }
          mx = sx / s; my = sy / s
          printf "%.6g %.6g %.6g %.6g %.6g\n", mx, my, sxx / s - mx * mx, syy / s - my * my, s }'
}
render() {  # render SCENE OUT BACKEND [options...]
  local scene=$1 out=$2 backend=$3; shift 3
  "$BIN" render "$scene" --backend "$backend" --spp ${SPP:-64} --quiet -o "$out" "$@" 2>"$T/err" ||
    { bad "$backend: render of $(basename "$scene") $*: $(cat "$T/err")"; return 1; }
}
pi=3.14159265358979

for backend in cpu opencl; do
  # Depth of field: a lamp at Z = 10 and Z = 10/3 with the focus at F = 5
  # and D = 1: |1/F - 1/Z| = 0.1 both, c = 0.1 film units, k = 32 / tan(10
  # deg) pixels per film unit at 64 x 64 and fov 20 (c k = 18 pixels). The
  # lamp, 0.04 film units wide at both depths, adds its square's variance
  # (side^2 / 12) and the pixels their box's (1/12, Sheppard). Measured (256
  # spp): within 1.5 % of the formula on both backends, both depths; bound 5 %.
  k=$(awk -v p=$pi 'BEGIN { print 32 / (sin(p / 18) / cos(p / 18)) }')
  for z in 10 3.3333333; do
    LS=$(awk -v z=$z 'BEGIN { print 0.02 * z }') LZ=$z lamp_scene "$T/dof.scene" 64 64 \
      position 0 0 0 direction 0 0 1 fov 20 aperture 1 focus 5
    SPP=256 render "$T/dof.scene" "$T/dof.exr" $backend || continue
    read -r cx cy vx vy s <<< "$(moments "$T/dof.exr")"
    want=$(awk -v k=$k -v z=$z 'BEGIN { c = 1 * (1/5 - 1/z); if (c < 0) c = -c
      sq = 0.04 * k; print (c * k) ^ 2 / 16 + sq * sq / 12 + 1 / 12 }')
    for v in "$vx" "$vy"; do
      near "$v" "$want" "$(awk -v w=$want 'BEGIN { print 0.05 * w }')" && ok ||
        bad "$backend: Z = $z: blur variance $v, the thin-lens circle of confusion gives $want"
    done
    near "$cx" 32 0.3 && near "$cy" 32 0.3 && ok || bad "$backend: Z = $z: blur centred at $cx $cy"
  done
  # Focused at the lamp ('lookat' without 'focus'), the lens images it as
  # the pinhole does: spreads within 0.03 pixel^2 (measured: equal); a focus
  # 5 % off would add (1 (1/9.5 - 1/10) k)^2 / 16 = 0.06.
  LS=0.1 lamp_scene "$T/sharp.scene" 64 64 position 0 0 0 lookat 0 0 10 fov 20 aperture 1
  LS=0.1 lamp_scene "$T/pinhole.scene" 64 64 position 0 0 0 lookat 0 0 10 fov 20
  render "$T/sharp.scene" "$T/sharp.exr" $backend &&
    read -r cx cy vx vy s <<< "$(moments "$T/sharp.exr")"
  render "$T/pinhole.scene" "$T/pinhole.exr" $backend &&
    read -r cx cy vx0 vy0 s <<< "$(moments "$T/pinhole.exr")"
  near "$vx" "$vx0" 0.03 && near "$vy" "$vy0" 0.03 && ok ||
    bad "$backend: focused at the lamp: spread $vx $vy, the pinhole's $vx0 $vy0"

  # Orthographic, 2 units wide: the unit lamp covers 32 of 64 columns, its
  # variance 32^2 / 12 + 1/12, from 10 units away and from 1000.
  for z in 10 1000; do
    LZ=$z lamp_scene "$T/ortho.scene" 64 64 position 0 0 0 direction 0 0 1 orthographic 2
    render "$T/ortho.scene" "$T/ortho-$z.exr" $backend &&
      read -r cx cy vx vy s <<< "$(moments "$T/ortho-$z.exr")"
    near "$vx" 85.42 1.5 && near "$vy" 85.42 1.5 && ok ||
      bad "$backend: orthographic at $z: spread $vx $vy (the lamp's 32 pixels give 85.4)"
  done
  # ... and `orthographic 2 vertical` on 128 x 64: 32 rows, 32 of 128 columns
  lamp_scene "$T/orthov.scene" 128 64 position 0 0 0 direction 0 0 1 orthographic 2 vertical
  render "$T/orthov.scene" "$T/orthov.exr" $backend &&
    read -r cx cy vx vy s <<< "$(moments "$T/orthov.exr")"
  near "$vx" 85.42 1.5 && near "$vy" 85.42 1.5 && near "$cx" 64 0.5 && ok ||
    bad "$backend: orthographic vertical: spread $vx $vy at x $cx"

  # fov 40 across the height of 128 x 64, or (the default) across its width:
  # the lamp, 0.1 film units, spans 0.1 * 32 / tan 20 or 0.1 * 64 / tan 20
  # pixels; variance w^2 / 12 + 1/12.
  for axis in vertical horizontal ""; do
    lamp_scene "$T/fov.scene" 128 64 position 0 0 0 direction 0 0 1 fov 40 $axis
    render "$T/fov.scene" "$T/fov.exr" $backend &&
      read -r cx cy vx vy s <<< "$(moments "$T/fov.exr")"
    half=64; [ "$axis" = vertical ] && half=32
    want=$(awk -v h=$half -v p=$pi 'BEGIN { t = sin(p / 9) / cos(p / 9); w = 0.1 * h / t
      print w * w / 12 + 1 / 12 }')
    near "$vx" "$want" "$(awk -v w=$want 'BEGIN { print 0.03 * w }')" && ok ||
      bad "$backend: fov 40 ${axis:-default}: spread $vx, want $want"
  done

  # Roll: the lamp at x = +2; with the default up (+y) it lies right of the
  # centre; with up +x, above it (image y small), on the centre column.
  LX=2 lamp_scene "$T/roll0.scene" 64 64 position 0 0 0 lookat 0 0 10 fov 40
  LX=2 lamp_scene "$T/roll.scene" 64 64 position 0 0 0 lookat 0 0 10 up 1 0 0 fov 40
  render "$T/roll0.scene" "$T/roll0.exr" $backend && read -r cx cy _ <<< "$(moments "$T/roll0.exr")"
  num "$cx" '>' 40 && near "$cy" 32 0.5 && ok || bad "$backend: default up: lamp at $cx $cy"
  render "$T/roll.scene" "$T/roll.exr" $backend && read -r cx cy _ <<< "$(moments "$T/roll.exr")"
  num "$cy" '<' 24 && near "$cx" 32 0.5 && ok || bad "$backend: up +x: lamp at $cx $cy"

  # The command line's camera against the same camera in the scene.
  LX=1 lamp_scene "$T/cl.scene" 48 32 position 0 0 -2 direction 0 0 1 fov 60 up 0 1 0
  LX=1 lamp_scene "$T/cl-same.scene" 48 32 position 0.5 -0.3 -1 lookat 0.2 0.1 10 up 0 1 0 fov 35
  render "$T/cl.scene" "$T/cl.exr" $backend --look-from 0.5,-0.3,-1 --look-at 0.2,0.1,10 --fov 35
  render "$T/cl-same.scene" "$T/cl-same.exr" $backend
  render "$T/cl.scene" "$T/cl-plain.exr" $backend
  check "$backend: --look-from/--look-at/--fov render the scene's own camera" \
    same_pixels "$T/cl.exr" "$T/cl-same.exr"
  check "$backend: ... which is not the file's camera" other_pixels "$T/cl.exr" "$T/cl-plain.exr"
  render "$T/cl.scene" "$T/cl-from.exr" $backend --look-from 0,0,-4
  read -r _ _ vx _ <<< "$(moments "$T/cl-from.exr")"
  read -r _ _ vx0 _ <<< "$(moments "$T/cl-plain.exr")"
  num "$vx" '<' "$vx0" && ok || bad "$backend: --look-from farther away: lamp spread $vx, not below $vx0"
done

# Errors: exit 2 naming the file and line, or the option.
expect_error() {  # expect_error WHAT PATTERN render-arguments...
  local what=$1 pat=$2; shift 2
  "$BIN" render "$@" --spp 1 --quiet -o "$T/never.png" > /dev/null 2> "$T/err"; local rc=$?
  [ $rc -eq 2 ] && grep -qE -- "$pat" "$T/err" && [ ! -e "$T/never.png" ] && ok ||
    bad "$what: exit $rc, $(cat "$T/err")"
}
for c in "fov 0.5" "fov 179.5" "fov 40 aperture 1" "orthographic 0" "fov 40 aperture -1 focus 2"; do
  lamp_scene "$T/bad.scene" 16 16 position 0 0 0 direction 0 0 1 $c
  expect_error "camera ... $c" "bad.scene:2:" "$T/bad.scene"
done
lamp_scene "$T/bad.scene" 16 16 position 0 0 0 lookat 0 0 0 fov 40
expect_error "lookat its own position" "bad.scene:2:.*looks at its own position" "$T/bad.scene"
lamp_scene "$T/ok.scene" 16 16 position 0 0 0 direction 0 0 1 up 0 1 0 fov 40
expect_error "--fov 180" "--fov" "$T/ok.scene" --fov 180
expect_error "--look-at 1,2" "--look-at" "$T/ok.scene" --look-at 1,2
expect_error "--look-at along up" "parallel to the camera's up" "$T/ok.scene" --look-at 0,5,0
# fov 1 and 179 are allowed now (MiniLight's own files keep its 10..160 clamp)
for f in 1 179; do
  lamp_scene "$T/edge.scene" 16 16 position 0 0 0 direction 0 0 1 fov $f
  "$BIN" render "$T/edge.scene" --backend cpu --spp 1 --quiet -o "$T/edge.png" 2>"$T/err" && ok ||
    bad "fov $f: $(cat "$T/err")"
done

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
