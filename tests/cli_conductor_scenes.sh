#!/bin/bash
# The conductor scenes and data: scenes/metals.scene and copper_sodium.scene are what
# tools/gen_meshes.py --metals writes, within the bundled scenes' triangle
# budget (tests/test_scenes_bundled.c); the bundled eta/k files
# (spectra/metal_*) carry their provenance and cover 380-780 nm with samples
# on both sides; each scene renders and its metal objects are in view. A
# binary that reads the conductor material renders the scenes as written;
# one that does not renders a Lambertian stand-in (each `conductor ...` clause
# replaced by a grey reflectance), which checks the geometry, camera, light
# and spectra files, not the metals.
# usage: bash tests/cli_conductor_scenes.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
R=(--backend cpu --quiet --width 24 --height 24 --spp 4 --seed 3)
mean_y() {  # mean of the first channel of an image (linear)
    oiiotool "$1" --printstats | awk '/Stats Avg/ { print $3; exit }'
}

# 1. The committed scenes are the generator's output, byte for byte.
python3 "$ROOT/tools/gen_meshes.py" --metals "$T/gen" > "$T/gen.list" ||
    { echo "FAIL: gen_meshes.py --metals"; exit 1; }
n=0
for f in "$T"/gen/*.scene; do
    n=$((n + 1))
    check "$(basename "$f") is committed as generated" cmp -s "$f" "$DATA/scenes/$(basename "$f")"
done
check "gen_meshes.py --metals wrote 2 scenes ($n)" test "$n" -eq 2

# 2. The triangle budget of a bundled scene (at most 200).
for f in "$DATA"/scenes/metals.scene "$DATA"/scenes/copper_sodium.scene; do
    tris=$(awk '$1 == "tri" { n++ } $1 == "quad" { n += 2 } END { print n + 0 }' "$f")
    check "$(basename "$f"): $tris triangles, 2..200" num "$tris" '<=' 200
    check "$(basename "$f"): has triangles" num "$tris" '>=' 2
done

# 3. The eta/k files: provenance first, the header, samples beyond both ends
#    of 380-780 nm, positive values; the loader reads them without a coverage
#    warning.
nf=0
for f in "$DATA"/spectra/metal_*_eta.csv "$DATA"/spectra/metal_*_k.csv; do
    [ -e "$f" ] || continue
    nf=$((nf + 1))
    b=$(basename "$f")
    check "$b: provenance line" grep -q '^# provenance: .*luxpop' <(head -1 "$f")
    check "$b: header" test "$(grep -v '^#' "$f" | head -1)" = "wavelength_nm,value"
    read -r first last minv <<< "$(grep -v '^#' "$f" | tail -n +2 |
        awk -F, 'NR == 1 { f = $1; m = $2 } { l = $1; if ($2 < m) m = $2 } END { print f, l, m }')"
    check "$b: first sample below 380 nm ($first)" num "$first" '<' 380
    check "$b: last sample above 780 nm ($last)" num "$last" '>' 780
    check "$b: values positive (min $minv)" num "$minv" '>' 0
    "$BIN" spectrum "$f" --emission --json > /dev/null 2> "$T/spec.err"
    check "$b: loads" test $? -eq 0
    check "$b: no coverage warning" test ! -s "$T/spec.err"
done
check "8 eta/k files (gold, silver, copper, aluminium; found $nf)" test "$nf" -eq 8

# 4. Rendering. Does this binary read the conductor material?
cat > "$T/probe.scene" << 'S'
image 8 8
camera position 0 0 -4 direction 0 0 1 fov 40
spectrum cu_eta file metal_Cu_eta.csv
spectrum cu_k file metal_Cu_k.csv
spectrum e equal
material cu conductor cu_eta cu_k
material lamp emit e 10
quad cu -1 -1 0  1 -1 0  1 1 0  -1 1 0
quad lamp -1 -1 -5  -1 1 -5  1 1 -5  1 -1 -5
S
if "$BIN" render "$T/probe.scene" "${R[@]}" -o "$T/probe.exr" > /dev/null 2>&1; then
    kind=conductor
else
    kind=stand-in
fi
echo "rendering the scenes as: $kind"
# the spheres the scenes place, beside the copies written here
cp "$DATA/scenes/materials_sphere.ply" "$T/"
for f in "$DATA"/scenes/metals.scene "$DATA"/scenes/copper_sodium.scene; do
    b=$(basename "$f" .scene)
    if [ "$kind" = conductor ]; then
        cp "$f" "$T/$b.scene"
    else
        sed -E 's/conductor [A-Za-z0-9_.-]+ [A-Za-z0-9_.-]+( alpha [0-9.eE+-]+)?/reflect white 0.8/' \
            "$f" > "$T/$b.scene"
        check "$b: the stand-in has no conductor left" test "$(grep -c "^material .* conductor " "$T/$b.scene")" -eq 0
    fi
    # the same scene with the metal objects black
    sed -E 's/^(material [a-z]+_(smooth|rough)) .*/\1/' "$T/$b.scene" > "$T/$b.black.scene"
    "$BIN" render "$T/$b.scene" "${R[@]}" -o "$T/$b.exr" > /dev/null 2> "$T/$b.err"
    rc=$?; check "$b: renders ($(head -c 300 "$T/$b.err"))" test $rc -eq 0
    check "$b: not black" num "$(mean_y "$T/$b.exr")" '>' 0
    "$BIN" render "$T/$b.black.scene" "${R[@]}" -o "$T/$b.black.exr" > /dev/null 2>&1
    check "$b: black-objects variant renders" test $? -eq 0
    # in view: more than 2 % of the pixels (the objects cover about 10 % at 24 x 24) change
    # by more than half the image's mean; objects out of view change the walls' light a little
    thr=$(awk -v m="$(mean_y "$T/$b.exr")" 'BEGIN { print 0.5 * m }')
    idiff -fail "$thr" -failpercent 2 -warn 1e30 "$T/$b.exr" "$T/$b.black.exr" > /dev/null 2>&1
    check "$b: the metal objects are in view (idiff: $?)" test $? -eq 2
done
finish
