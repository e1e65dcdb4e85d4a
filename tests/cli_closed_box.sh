#!/bin/bash
# A walk leaving a point on an edge of a closed box stays in it: lamp_room
# with its shade closed by a lid of its metal is black under the path, light
# and bidirectional tracers (CPU reference) at sizes and seeds where light
# once escaped through the edges: a hit on an edge lay, by rounding, just
# outside the neighbouring face, whose hit was then at t <= 0 and did not
# count (light tracer 48 x 48, 32 spp, seed 2: brightest pixel 1.6; bdpt
# seed 3: 3.8). A ray now leaves a surface from a point a margin inside the
# triangle's edges and off its plane (host/geometry/bvh.c spm_ray_spawn);
# test_cl_box_edges checks the kernel's traversal against the reference's
# on such rays.
source "$(dirname "$0")/lib_cli.sh"

sed 's/^# the glass egg.*/quad shade  0.765 0.500 0.745  0.835 0.500 0.745  0.835 0.500 0.815  0.765 0.500 0.815/' \
    "$DATA/scenes/lamp_room.scene" > "$T/closed.scene"
cp "$DATA/scenes/materials_sphere.ply" "$T/"
check "the closed lamp has its lid" grep -q "^quad shade  0.765 0.500" "$T/closed.scene"
for run in "light 2" "bdpt 3" "path 2"; do
    set -- $run
    "$BIN" render "$T/closed.scene" --integrator $1 --backend cpu --width 48 --height 48 \
        --spp 32 --seed $2 --quiet -o "$T/closed-$1.exr" 2> "$T/closed-$1.err"
    mx=$(oiiotool "$T/closed-$1.exr" --printstats | awk '/Stats Max/ { print $3 + $4 + $5; exit }')
    check "closed lamp, $1, seed $2: black (max $mx)" test "$mx" = 0
done
finish
