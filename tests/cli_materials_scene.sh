#!/bin/bash
# scenes/materials.scene (gold, a coating, clear, green and rough glass on
# smooth-normal spheres) and its mesh are what tools/gen_meshes.py
# --materials writes; it renders in every mode on both backends; its objects
# are in view (black, they change the image) and shade smooth (the same
# spheres `flat` change it); on the same paths ml stays within T = 2 dE00 of
# truth at the 99th percentile on each backend.
# usage: bash tests/cli_materials_scene.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
R=(--quiet --width 48 --height 48 --spp 8 --seed 3)
mean_y() {  # mean of the first channel of an image (linear)
    oiiotool "$1" --printstats | awk '/Stats Avg/ { print $3; exit }'
}
p99() {  # p99 dE00 of B against A
    "$BIN" compare "$1" "$2" --json | python3 -c 'import json, sys; print(json.load(sys.stdin)["p99"])'
}

# 1. The committed scene and mesh are the generator's output, byte for byte.
python3 "$ROOT/tools/gen_meshes.py" --materials "$T/gen" > "$T/gen.list" ||
    { echo "FAIL: gen_meshes.py --materials"; exit 1; }
n=0
for f in "$T"/gen/*; do
    n=$((n + 1))
    check "$(basename "$f") is committed as generated" cmp -s "$f" "$DATA/scenes/$(basename "$f")"
done
check "gen_meshes.py --materials wrote 2 files ($n)" test "$n" -eq 2

# 2. Every mode on both backends; ml against truth on the same paths.
f="$DATA/scenes/materials.scene"
modes=$("$BIN" modes | cut -f1)
check "modes listed" test -n "$modes"
for b in cpu opencl; do
    for m in $modes; do
        "$BIN" render "$f" "${R[@]}" --backend $b --mode $m -o "$T/$b.$m.exr" > /dev/null 2> "$T/$b.$m.err"
        rc=$?; check "$b $m: renders ($(grep -v 'triangles, bounding box' "$T/$b.$m.err" | head -c 300))" test $rc -eq 0
        check "$b $m: not black" num "$(mean_y "$T/$b.$m.exr")" '>' 0
    done
    e=$(p99 "$T/$b.truth.exr" "$T/$b.ml.exr")
    echo "materials, $b: ml p99 dE00 $e against truth, rgb $(p99 "$T/$b.truth.exr" "$T/$b.rgb.exr")"
    check "materials $b: ml p99 $e <= 2" num "$e" '<=' 2
done

# 3. The objects are in view, and smooth: black spheres, flat spheres.
sed -E 's/^(material [a-z]+) +(conductor|coated|dielectric) .*/\1/' "$f" > "$T/black.scene"
check "the black variant has none of the types left" \
    test "$(grep -cE ' (conductor|coated|dielectric) ' "$T/black.scene")" -eq 0
sed -E 's/^(mesh .*)$/\1 flat/' "$f" > "$T/flat.scene"
check "the flat variant has 5 flat meshes" test "$(grep -c '^mesh .* flat$' "$T/flat.scene")" -eq 5
for v in black flat; do
    sed -i "s|materials_sphere.ply|$DATA/scenes/materials_sphere.ply|" "$T/$v.scene"
    "$BIN" render "$T/$v.scene" "${R[@]}" --backend cpu --mode truth -o "$T/$v.exr" > /dev/null 2>&1
    check "$v variant renders" test $? -eq 0
done
thr=$(awk -v m="$(mean_y "$T/cpu.truth.exr")" 'BEGIN { print 0.5 * m }')
idiff -fail "$thr" -failpercent 2 -warn 1e30 "$T/cpu.truth.exr" "$T/black.exr" > /dev/null 2>&1
check "the spheres are in view (idiff: $?)" test $? -eq 2
other_pixels "$T/cpu.truth.exr" "$T/flat.exr" && ok || bad "the spheres do not shade smooth"
finish
