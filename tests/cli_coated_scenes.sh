#!/bin/bash
# The coated scenes: scenes/coated.scene and coated_spiky.scene are what
# tools/gen_meshes.py --coated writes, within the bundled scenes' triangle
# budget (tests/test_scenes_bundled.c); each renders, and its coated objects
# are in view (black, they change the image); the pretest's table (--verbose)
# judges every coated material's derived colour, NAME:effective.
# usage: bash tests/cli_coated_scenes.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
R=(--backend cpu --quiet --width 24 --height 24 --spp 4 --seed 3)
mean_y() {  # mean of the first channel of an image (linear)
    oiiotool "$1" --printstats | awk '/Stats Avg/ { print $3; exit }'
}

python3 "$ROOT/tools/gen_meshes.py" --coated "$T/gen" > "$T/gen.list" ||
    { echo "FAIL: gen_meshes.py --coated"; exit 1; }
n=0
for f in "$T"/gen/*.scene; do
    n=$((n + 1))
    check "$(basename "$f") is committed as generated" cmp -s "$f" "$DATA/scenes/$(basename "$f")"
done
check "gen_meshes.py --coated wrote 2 scenes ($n)" test "$n" -eq 2

for f in "$DATA"/scenes/coated.scene "$DATA"/scenes/coated_spiky.scene; do
    b=$(basename "$f" .scene)
    tris=$(awk '$1 == "tri" { n++ } $1 == "quad" { n += 2 } END { print n + 0 }' "$f")
    check "$b: $tris triangles, 2..200" num "$tris" '<=' 200
    check "$b: has coated materials" test "$(grep -c '^material .* coated ' "$f")" -ge 4
    "$BIN" render "$f" "${R[@]}" -o "$T/$b.exr" > /dev/null 2> "$T/$b.err"
    rc=$?; check "$b: renders ($(head -c 300 "$T/$b.err"))" test $rc -eq 0
    check "$b: not black" num "$(mean_y "$T/$b.exr")" '>' 0
    "$BIN" render "$f" "${R[@]}" --mode ml --verbose -o "$T/$b.v.exr" > "$T/$b.v" 2>&1
    for m in $(awk '$1 == "material" && $3 == "coated" { print $2 }' "$f"); do
        check "$b: the pretest judges $m:effective" grep -q "^$m:effective .*chosen level" "$T/$b.v"
    done
    # the coated objects black: more than 2 % of the pixels change by half the mean
    sed -E 's/^(material [a-z_]+) +coated .*/\1/' "$f" > "$T/$b.black.scene"
    check "$b: the black variant has no coating" test "$(grep -c '^material .* coated ' "$T/$b.black.scene")" -eq 0
    "$BIN" render "$T/$b.black.scene" "${R[@]}" -o "$T/$b.black.exr" > /dev/null 2>&1
    check "$b: black-objects variant renders" test $? -eq 0
    thr=$(awk -v m="$(mean_y "$T/$b.exr")" 'BEGIN { print 0.5 * m }')
    idiff -fail "$thr" -failpercent 2 -warn 1e30 "$T/$b.exr" "$T/$b.black.exr" > /dev/null 2>&1
    check "$b: the coated objects are in view (idiff: $?)" test $? -eq 2
done
finish
