#!/bin/bash
# scenes/ball_lens.scene's focus against the ball-lens formula: a glass ball
# of radius R = 0.5 and index n = 1.5 has focal length f = n R / (2 (n - 1))
# = 0.75 from its centre (where its principal planes are), so the lamp s = 3
# above the centre is imaged s' = f s / (s - f) = 1 below it (1/s + 1/s' =
# 1/f). The lamp becomes a spot light of half-angle atan(h / s), h = 0.05
# (0.1 R: paraxial rays, whose spherical aberration an exact trace of the
# sphere puts at 1 % of the spot), and the floor moves to D = 2 below the
# centre: each ray crosses the centre plane at height up to h and the axis
# s' below, so the light covers a disc of radius r = h (D - s') / s' = 0.05.
# Seen from 3 before its centre and 1 above the floor at fov 6 on 64 pixels,
# that disc's middle chord is 2 r / sqrt(10) / tan(3 deg) x 32 = 19.31
# pixels, measured as each row's sum over the disc's plateau (a pixel's
# splats cover its share of the disc): within one pixel (measured 19.82 at
# seed 1, 19.5 from the exact trace; with n = 1.6 it would be 25.7).
source "$(dirname "$0")/lib_cli.sh"
sed -e 's/^light point 0 4 0 white 30$/light spot 0 4 0  0 -1 0  white intensity 30 cone 0.95493 falloff 0/' \
    -e 's/^quad floor .*/quad floor  -1 -1 -1  -1 -1 1  1 -1 1  1 -1 -1/' \
    -e 's/^camera .*/camera position 0 0 -3  direction 0 -1 3  fov 6/' \
    -e 's/^image .*/image 64 64/' \
    -e "s#materials_sphere.ply#$DATA/scenes/materials_sphere.ply#" \
    "$DATA/scenes/ball_lens.scene" > "$T/spot.scene"
check "the variant has its spot, floor and camera" \
    test "$(grep -c -e 'cone 0.95493' -e '^quad floor  -1 -1' -e 'fov 6$' "$T/spot.scene")" = 3
"$BIN" render "$T/spot.scene" --integrator light --backend cpu --spp 16 --seed 1 --quiet \
    -o "$T/spot.exr"
check "render: exit 0" test $? -eq 0
# each pixel's Y (the middle channel) as "row value"; the plateau's level is
# the median over the pixels above half the brightest
oiiotool --dumpdata "$T/spot.exr" |
    sed -n 's/^ *Pixel ([0-9]*, \([0-9]*\)): [^ ]* \([^ ]*\) .*/\1 \2/p' > "$T/y.txt"
check "the image's pixels read" test "$(grep -c . "$T/y.txt")" = 4096
max=$(sort -k2 -g "$T/y.txt" | tail -1 | cut -d' ' -f2)
awk -v m="$max" '$2 > 0.5 * m { print $2 }' "$T/y.txt" | sort -g > "$T/lit.txt"
k=$(grep -c . "$T/lit.txt")
med=$(awk -v k="$k" 'NR == int((k + 1) / 2) { a = $1 } NR == int(k / 2) + 1 { b = $1 }
    END { print k % 2 ? a : (a + b) / 2 }' "$T/lit.txt")
chord=$(awk -v med="$med" -v k="$k" '{ s[$1] += $2 }
    END { if (k <= 4) { print -1; exit } for (r in s) if (s[r] / med > c) c = s[r] / med; printf "%.3f", c }' "$T/y.txt")
expect=$(awk 'BEGIN { n = 1.5; R = 0.5; s = 3; D = 2; h = 0.05
    f = n * R / (2 * (n - 1)); sp = f * s / (s - f); r = h * (D - sp) / sp
    printf "%.3f", 2 * r / sqrt(10) / (sin(3 * atan2(0, -1) / 180) / cos(3 * atan2(0, -1) / 180)) * 32 }')
echo "the spot's middle chord: $chord pixels, the ball-lens formula's $expect"
check "the spot where the ball-lens formula puts it (within a pixel)" near "$chord" "$expect" 1
finish
