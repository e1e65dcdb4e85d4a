#!/bin/bash
# 'emit SPECTRUM L twosided': a light turned away from the floor lights it
# only when set (next-event estimation), and its back face is seen bright
# only when set (emission at a hit), on both backends.
# usage: bash tests/cli_twosided.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

scene() {  # scene FILE [twosided]: a floor under a light whose front faces up
  cat > "$1" <<SCENE
image 32 24
spp 16
camera position 0 0.5 -3  direction 0 -0.1 1  fov 60
spectrum equal equal
material floor reflect equal 0.5
material lamp  emit equal 10 $2
quad floor  -2 0 -2  -2 0 2  2 0 2  2 0 -2
quad lamp   -0.5 1 -0.5  -0.5 1 0.5  0.5 1 0.5  0.5 1 -0.5
SCENE
}
mean_y() {  # mean_y EXR: the image's mean of R + G + B
  oiiotool "$1" --printstats 2>/dev/null |
    awk -F: '/Stats Avg/ { split($2, v, " "); print v[1] + v[2] + v[3]; exit }'
}
scene "$T/one.scene" ""
scene "$T/two.scene" twosided
for backend in opencl cpu; do
  for s in one two; do
    "$BIN" render "$T/$s.scene" --backend $backend --quiet -o "$T/$s-$backend.exr" 2>"$T/err" ||
      bad "$backend: render of $s.scene: $(cat "$T/err")"
  done
  one=$(mean_y "$T/one-$backend.exr") two=$(mean_y "$T/two-$backend.exr")
  # one-sided, turned away: nothing reaches the floor, the back is black
  num "$one" == 0 && ok || bad "$backend: a light facing away lights the scene: mean $one"
  num "$two" '>' 0.05 && ok || bad "$backend: twosided light lights nothing: mean $two"
  # the light's underside is in view: seen at its emission (10, a flat
  # spectrum: G about 10), where a one-sided light shows black
  c=$(oiiotool "$T/two-$backend.exr" --printstats 2>/dev/null |
      awk -F: '/Stats Max/ { split($2, v, " "); print v[2]; exit }')
  num "$c" '>' 5 && ok || bad "$backend: the back face of a twosided light is not bright: max $c"
done
finish
