#!/bin/bash
# The hints on a render that shows nothing (warnings, exit status 0): a black
# image, the camera inside a closed mesh, an emitter that lights nothing the
# camera can see. Each prints on a scene made to cause it and on no other,
# nor on the Cornell box. The CPU reference renders (no OpenCL device).
# usage: bash tests/cli_hints.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

# a unit cube, closed (12 triangles, every edge on two), and with its +x face left out
cat > "$T/cube.obj" <<'OBJ'
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
OBJ
grep -v '^f 2 3 7 6' "$T/cube.obj" > "$T/open.obj"
scene() {  # scene NAME CAMERA_LINE [STATEMENT...]: a floor lit by a lamp facing it
  local name=$1 cam=$2
  shift 2
  { cat <<SCENE
image 32 24
spp 4
spectrum equal equal
material floor reflect equal 0.5
material lamp  emit equal 10
quad floor  -2 0 -2  -2 0 2  2 0 2  2 0 -2
quad lamp   -0.5 1 -0.5  0.5 1 -0.5  0.5 1 0.5  -0.5 1 0.5
$cam
SCENE
    printf '%s\n' "$@"; } > "$T/$name.scene"
}
look='camera position 0 0.5 -1.5  direction 0 -0.1 1  fov 60'
# a model in millimetres: the cube 3 units across each way encloses camera and lamp
scene inside "$look" 'mesh cube.obj material floor scale 3'
scene open "$look" 'mesh open.obj material floor scale 3'
scene outside "$look" 'mesh cube.obj material floor scale 0.2 translate 0 0.2 0'
# a second lamp above the first, facing up, the camera below it
up='quad up  -0.5 1.5 -0.5  -0.5 1.5 0.5  0.5 1.5 0.5  0.5 1.5 -0.5'
scene away "$look" 'material up emit equal 20' "$up"
scene away_twosided "$look" 'material up emit equal 20 twosided' "$up"
# one of the material's quads faces away, its other one the floor
scene half "$look" 'material up emit equal 20' "$up" \
  'quad up  -0.5 1.2 -0.5  0.5 1.2 -0.5  0.5 1.2 0.5  -0.5 1.2 0.5'
# the camera above both: it sees the lamp facing up, and is behind the one
# facing the floor
scene seen 'camera position 0 2.5 -3  direction 0 -0.5 1  fov 60' 'material up emit equal 20' "$up"
# the camera looks away from everything
scene black 'camera position 0 0.5 -3  direction 0 0 -1  fov 60'

render() {  # render NAME [ARGS...]: stderr in $T/NAME.err; its exit status must be 0
  local name=$1
  shift
  "$BIN" render "$@" --backend cpu --quiet -o "$T/$name.exr" 2> "$T/$name.err"
  local rc=$?
  [ $rc -eq 0 ] && ok || bad "$name: exit $rc: $(cat "$T/$name.err")"
}
for s in inside open outside away away_twosided seen half black; do
  render $s "$T/$s.scene"
done
render cornell --spp 1 --width 32 --height 32

BLACK='warning: the image is black'
INSIDE='warning: .*camera inside the closed mesh'
IDLE='warning: emitter material'
hints() {  # hints NAME PATTERN: how many lines of NAME's stderr match
  grep -c -- "$2" "$T/$1.err"
}
# each hint on its scene, naming the cause
check "black: the black-image hint" [ "$(hints black "$BLACK")" -eq 1 ]
check "inside: the closed-mesh hint naming cube.obj and its box" \
  [ "$(hints inside "${INSIDE} 'cube.obj' (bounding box (-3 -3 -3) to (3 3 3)")" -eq 1 ]
check "away: one emitter hint for material 'up' (two triangles)" \
  [ "$(hints away "$IDLE 'up' .* its 2 triangles")" -eq 1 ]
# and on no other scene (so a hint that always prints fails)
for s in inside open outside away away_twosided seen half cornell; do
  check "$s: black-image hint on an image that is not black" [ "$(hints $s "$BLACK")" -eq 0 ]
done
for s in open outside away away_twosided seen half black cornell; do
  check "$s: closed-mesh hint" [ "$(hints $s "$INSIDE")" -eq 0 ]
done
for s in inside open outside away_twosided seen half black cornell; do
  check "$s: emitter hint" [ "$(hints $s "$IDLE")" -eq 0 ]
done
# the images themselves: black only where the hint says so
for s in black inside away; do
  m=$(oiiotool "$T/$s.exr" --printstats 2>/dev/null |
      awk -F: '/Stats Max/ { split($2, v, " "); print v[1] + v[2] + v[3]; exit }')
  if [ $s = black ]; then
    check "$s: image max $m, expected 0" num "$m" == 0
  else
    check "$s: image max $m, expected > 0" num "$m" '>' 0
  fi
done
finish
