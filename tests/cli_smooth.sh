#!/bin/bash
# Smooth shading lets no light through or under the geometric surface: a
# quad whose vertex normals lean 60 degrees from its face (tools/gen_meshes.py
# tilt.obj), seen from its front, with a lit wall behind it, renders black on
# both backends, whether diffuse (`smooth`), a rough or a smooth conductor;
# with the light in front of it instead, the same quad is lit (the scene can
# show light). Then the mesh statement's clauses: `flat` turns smooth shading
# off, `smooth` turns it on for a diffuse material, and a diffuse mesh without
# `smooth` renders as before (flat).
# usage: bash tests/cli_smooth.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

python3 "$ROOT/tools/gen_meshes.py" "$T" > /dev/null || { echo "FAIL: gen_meshes.py"; exit 1; }
max_sum() {  # max_sum EXR: the image's largest R + G + B of a pixel's maxima
  oiiotool "$1" --printstats 2>/dev/null |
    awk -F: '/Stats Max/ { split($2, v, " "); print v[1] + v[2] + v[3]; exit }'
}
for backend in cpu opencl; do
  for kind in diffuse rough mirror; do
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
finish
