#!/bin/bash
# Smooth shading lets no light through or under the geometric surface: a
# quad whose vertex normals lean 60 degrees from its face (tools/gen_meshes.py
# tilt.obj), seen from its front, with a lit wall behind it, renders black on
# both backends, whether diffuse (`smooth`), a rough or a smooth conductor, a
# smooth or a rough coating; with the light in front of it instead, the same
# quad is lit (the scene can show light). A smooth clear glass sphere in a
# uniform background (invisible.scene) is invisible in every mode on both
# backends, but for the paths the leak rule ends. Then the mesh statement's
# clauses: `flat` turns smooth shading off, `smooth` turns it on for a
# diffuse material, and a diffuse mesh without `smooth` renders as before
# (flat).
# usage: bash tests/cli_smooth.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

python3 "$ROOT/tools/gen_meshes.py" "$T" > /dev/null || { echo "FAIL: gen_meshes.py"; exit 1; }
max_sum() {  # max_sum EXR: the image's largest R + G + B of a pixel's maxima
  oiiotool "$1" --printstats 2>/dev/null |
    awk -F: '/Stats Max/ { split($2, v, " "); print v[1] + v[2] + v[3]; exit }'
}
for backend in cpu opencl; do
  for kind in diffuse rough mirror paint satin; do
    "$BIN" render "$T/leak_$kind.scene" --backend $backend --spp 64 --quiet \
        -o "$T/leak_$kind-$backend.exr" 2>"$T/err" ||
      bad "$backend: render of leak_$kind.scene: $(cat "$T/err")"
    m=$(max_sum "$T/leak_$kind-$backend.exr")
    num "$m" == 0 && ok || bad "$backend: $kind: light leaks through the quad: max $m"
    [ "$kind" = mirror ] && continue # its mirror direction lies at the horizon: nothing there
    "$BIN" render "$T/leak_lit_$kind.scene" --backend $backend --spp 64 --quiet \
        -o "$T/lit_$kind-$backend.exr" 2>"$T/err" ||
      bad "$backend: render of leak_lit_$kind.scene: $(cat "$T/err")"
    m=$(max_sum "$T/lit_$kind-$backend.exr")
    num "$m" '>' 0.1 && ok || bad "$backend: $kind: the quad lit from the front is black: max $m"
  done
done

# The invisible sphere against the background alone (the mesh replaced by a
# glass triangle out of view): the image over the background's, per channel.
# Measured (64 spp): mean 1 - 1.07e-4 and the darkest pixel 1 - 1/64 (one
# path of its 64 ended by the leak rule or truncated) in every mode but hero,
# whose 4 wavelengths a path add colour noise (means within 1e-3, pixels within
# 0.19); bounds: mean 1e-3 off (hero 5e-3), a pixel 2/64 darker (hero 0.3),
# none brighter than 1 + 1e-5 (float rounding of equal weights).
sed 's/^mesh .*/tri clear 100 100 100  101 100 100  100 101 100/' "$T/invisible.scene" > "$T/bg.scene"
"$BIN" render "$T/bg.scene" --backend cpu --spp 64 --quiet -o "$T/bg.exr" 2>"$T/err" ||
  bad "render of the background alone: $(cat "$T/err")"
stat3() {  # stat3 STAT EXR: the STAT (Avg, Min, Max) of the image's three channels, one a line
  oiiotool "$2" --printstats 2>/dev/null | awk -v s="Stats $1:" 'index($0, s) { print $3; print $4; print $5; exit }'
}
for backend in cpu opencl; do
  for mode in $("$BIN" modes | cut -f1); do
    "$BIN" render "$T/invisible.scene" --backend $backend --mode $mode --spp 64 --quiet         -o "$T/inv.exr" 2>"$T/err" || bad "$backend $mode: render of invisible.scene: $(cat "$T/err")"
    oiiotool "$T/inv.exr" "$T/bg.exr" --div -o "$T/ratio.exr" 2>/dev/null
    tol=1e-3 dark=$(awk 'BEGIN { print 1 - 2 / 64 }') bright=1.00001
    [ "$mode" = hero ] && tol=5e-3 dark=0.7 bright=1.3
    for c in $(stat3 Avg "$T/ratio.exr"); do
      near "$c" 1 "$tol" && ok || bad "$backend $mode: the glass sphere shows: mean $c of the background"
    done
    for c in $(stat3 Min "$T/ratio.exr"); do
      num "$c" '>=' "$dark" && ok || bad "$backend $mode: a pixel is $c of the background"
    done
    for c in $(stat3 Max "$T/ratio.exr"); do
      num "$c" '<=' "$bright" && ok || bad "$backend $mode: a pixel is $c of the background"
    done
  done
done

# the clauses: the diffuse sphere of smooth_box.scene smooth, flat, and without
# either (flat: the same image as with `flat`); the smooth one differs
sed 's/^mesh sphere_n.ply material white smooth/mesh sphere_n.ply material white flat/' \
    "$T/smooth_box.scene" > "$T/flat.scene"
sed 's/^mesh sphere_n.ply material white smooth/mesh sphere_n.ply material white/' \
    "$T/smooth_box.scene" > "$T/default.scene"
for s in smooth_box flat default; do
  "$BIN" render "$T/$s.scene" --backend cpu --width 48 --height 48 --spp 4 --quiet \
      -o "$T/$s.exr" 2>"$T/$s.err" || bad "render of $s.scene: $(cat "$T/$s.err")"
done
same_pixels "$T/flat.exr" "$T/default.exr" && ok || bad "a diffuse mesh without 'smooth' is not flat"
other_pixels "$T/flat.exr" "$T/smooth_box.exr" && ok || bad "'smooth' changes nothing"
check "diffuse mesh with normals, no 'smooth': the normals are said to be ignored" \
    grep -q "vertex normals ignored (diffuse materials shade flat unless the mesh statement says 'smooth'" "$T/default.err"
check "'smooth': nothing said of normals" eval '! grep -q "vertex normals" "$T/smooth_box.err"'
sed 's/^mesh sphere_n.obj material tall_box/mesh sphere_n.obj material tall_box flat/' \
    "$T/flat.scene" > "$T/allflat.scene"
"$BIN" render "$T/allflat.scene" --backend cpu --width 48 --height 48 --spp 4 --quiet \
    -o "$T/allflat.exr" 2>"$T/err" || bad "render of allflat.scene: $(cat "$T/err")"
other_pixels "$T/flat.exr" "$T/allflat.exr" && ok || bad "a conductor mesh with normals does not shade smooth by default"
printf 'image 8 8\ncamera position 0 0 -3 direction 0 0 1 fov 40\nspectrum e inline 380 1 780 1 end\nmaterial m reflect e 0.5\nmesh sphere_n.obj material m smooth flat\n' > "$T/both.scene"
"$BIN" render "$T/both.scene" --quiet -o "$T/x.exr" 2>"$T/err"
check "'smooth flat': refused (exit 2)" test $? -eq 2
check "'smooth flat': the message names the clause" grep -q "both.scene:5:.*'smooth' or 'flat' (once)" "$T/err"

# `smooth` on a mesh without vertex normals computes them (angle-weighted,
# broken at edges sharper than the crease angle, 60 degrees by default): the
# mirror sphere of sphere_n.obj without its `vn` lines renders as the sphere
# with its analytic normals, the same seed, and not as the faceted one.
# Measured (64 x 64, 16 spp, mean absolute difference per channel): computed
# against analytic 0.77, flat against analytic 3.36 (another seed: 8.6, so the
# same seed's paths are compared); bound: half the flat sphere's difference.
# A cube (every edge 90 degrees) stays faceted: 2.2e-7 from the flat cube
# (float rounding of the rotated normals), bound 1e-3; under 'crease 100' its
# corners round (2.56), bound 0.5.
grep -v '^vn' "$T/sphere_n.obj" | sed 's|//[0-9]*||g' > "$T/sphere_nn.obj"
grep -v '^mesh' "$T/smooth_box.scene" > "$T/nobox.scene"
mean_diff() { idiff "$1" "$2" 2>/dev/null | awk '/Mean error/ { print $4 }'; }
for k in "n:sphere_n.obj material tall_box smooth" "c:sphere_nn.obj material tall_box smooth" \
         "f:sphere_nn.obj material tall_box" "cs:cube.obj material tall_box smooth" \
         "cf:cube.obj material tall_box" "cr:cube.obj material tall_box smooth crease 100"; do
  n=${k%%:*} place="scale 0.15 translate 0.278 0.2 0.25"
  [ "${n:0:1}" = c ] && [ "$n" != c ] && place="rotate 0 1 0 30 scale 0.08 translate 0.2 0 0.2"
  { cat "$T/nobox.scene"; echo "mesh ${k#*:} $place"; } > "$T/n_$n.scene"
  "$BIN" render "$T/n_$n.scene" --backend cpu --width 64 --height 64 --spp 16 --seed 3 \
      -o "$T/n_$n.exr" 2> "$T/n_$n.err" || bad "render of n_$n.scene: $(cat "$T/n_$n.err")"
done
check "'smooth' without vertex normals: the note counts the triangles given computed ones" \
    grep -q "sphere_nn.obj: 'smooth': vertex normals computed for 224 triangles the file gives none (crease 60 degrees)" "$T/n_c.err"
check "with the file's own normals nothing is computed" eval '! grep -q "computed" "$T/n_n.err"'
dc=$(mean_diff "$T/n_n.exr" "$T/n_c.exr") df=$(mean_diff "$T/n_n.exr" "$T/n_f.exr")
num "$df" '>' 1 && ok || bad "the flat sphere is not different from the smooth one: $df"
num "$dc" '<' "$(awk -v d="$df" 'BEGIN { print d / 2 }')" && ok ||
  bad "the computed normals' sphere is $dc from the analytic one's, the flat sphere's $df"
d=$(mean_diff "$T/n_cf.exr" "$T/n_cs.exr")
num "$d" '<' 1e-3 && ok || bad "the smoothed cube is not faceted under the crease of 60: $d from flat"
d=$(mean_diff "$T/n_cf.exr" "$T/n_cr.exr")
num "$d" '>' 0.5 && ok || bad "under 'crease 100' the cube's corners do not round: $d from flat"
printf 'image 8 8\ncamera position 0 0 -3 direction 0 0 1 fov 40\nspectrum e inline 380 1 780 1 end\nmaterial m reflect e 0.5\nmesh sphere_nn.obj material m crease 30\n' > "$T/crease.scene"
"$BIN" render "$T/crease.scene" --quiet -o "$T/x.exr" 2>"$T/err"
check "'crease' without 'smooth': refused (exit 2)" test $? -eq 2
check "'crease' without 'smooth': the message says so" grep -q "crease.scene:5:1: 'crease' (line 5) applies to the normals 'smooth' computes" "$T/err"
sed -i 's/crease 30/smooth crease 0.5/' "$T/crease.scene"
"$BIN" render "$T/crease.scene" --quiet -o "$T/x.exr" 2>"$T/err"
check "'crease 0.5': refused (exit 2)" test $? -eq 2
check "'crease 0.5': the message gives the range" grep -q "crease.scene:5:.*crease angle in degrees" "$T/err"
finish
