#!/bin/bash
# specmip compare on images made with oiiotool: known differences in the JSON,
# 8-bit decoding, the heat map, and exit code 2 with a clear message on bad input.
source "$(dirname "$0")/lib_cli.sh"

# Reference: uniform linear grey 1 (so Yn = 1 and L* = 100). Test image: the grey
# of L* = 90. Greys differ in L* only: dE*ab = 10, dE00 = 10 / S_L at L = 95.
g90=$(awk 'BEGIN { printf "%.9f", ((90 + 16) / 116) ^ 3 }')
de00=$(awk 'BEGIN { d = 45 * 45; printf "%.6f", 10 / (1 + 0.015 * d / sqrt(20 + d)) }')
oiiotool --pattern constant:color=1,1,1 16x12 3 -d float -o "$T/a.exr"
oiiotool --pattern constant:color=$g90,$g90,$g90 16x12 3 -d float -o "$T/b.exr"
oiiotool --pattern constant:color=1,1,1 16x12 3 -d uint8 -o "$T/c.png"
oiiotool --pattern constant:color=1,1,1 8x8 3 -d float -o "$T/small.exr"
check "test images made" test -s "$T/a.exr" -a -s "$T/b.exr" -a -s "$T/c.png" -a -s "$T/small.exr"
echo "not an image" > "$T/garbage.exr"

"$BIN" compare "$T/a.exr" "$T/a.exr" --json > "$T/same.json"
check "identical images: exit 0" test $? -eq 0
check "identical images: mean 0" num "$(jnum "$T/same.json" '.mean + .max + .dEab_max')" == 0
check "identical images: all pixels in bucket <1" test "$(jq '.buckets[0]' "$T/same.json")" = 192

# The greys' chromaticity (sRGB matrix white) and colour.h's D65 differ in the 4th
# digit; that adds < 1e-4 to these differences, so 1e-3 is a safe tolerance.
"$BIN" compare "$T/a.exr" "$T/b.exr" --json > "$T/shift.json" 2> "$T/shift.err"
check "L* shift: exit 0" test $? -eq 0
check "two linear images: no warning" test ! -s "$T/shift.err"
check "L* shift: dEab_mean 10" near "$(jnum "$T/shift.json" .dEab_mean)" 10 1e-3
check "L* shift: dEab_p99 10" near "$(jnum "$T/shift.json" .dEab_p99)" 10 1e-3
check "L* shift: mean dE00 = 10/S_L" near "$(jnum "$T/shift.json" .mean)" "$de00" 1e-3
check "L* shift: white from A" near "$(jnum "$T/shift.json" .white_y)" 1 1e-6
check "L* shift: dE00 buckets" test "$(jq -c .buckets "$T/shift.json")" = "[0,0,0,0,0,192]"

"$BIN" compare "$T/a.exr" "$T/b.exr" --white-y 2 --json > "$T/white.json"
check "--white-y: exit 0" test $? -eq 0
check "--white-y is used" near "$(jnum "$T/white.json" .white_y)" 2 1e-9

# An 8-bit image holds sRGB codes: 255 decodes to linear 1, equal to a.exr.
"$BIN" compare "$T/a.exr" "$T/c.png" --json > "$T/png.json" 2> "$T/png.err"
check "8-bit PNG: exit 0" test $? -eq 0
check "linear against 8-bit codes: warned as unlike encodings" \
    grep -q "warning: .*a.exr is linear light and .*c.png display-encoded" "$T/png.err"
check "8-bit white equals linear 1" near "$(jnum "$T/png.json" .max)" 0 1e-4

"$BIN" compare "$T/a.exr" "$T/b.exr" > "$T/table.txt"
check "table: exit 0" test $? -eq 0
check "table output has both metrics" grep -q "^dE\*ab" "$T/table.txt"

"$BIN" compare "$T/a.exr" "$T/b.exr" --heatmap "$T/heat.png" > /dev/null
check "heat map: exit 0" test $? -eq 0
check "heat map written" test -s "$T/heat.png"
check "heat map size: map, bar, labels" test "$(oiiotool "$T/heat.png" --echo '{TOP.width}x{TOP.height}' 2>/dev/null)" = "47x128"

expect_exit2() {  # expect_exit2 WHAT PATTERN ARGS...
    local what=$1 pattern=$2; shift 2
    "$BIN" compare "$@" > /dev/null 2> "$T/err.txt"
    local rc=$?
    check "$what: exit 2 (got $rc)" test $rc -eq 2
    check "$what: message matches '$pattern'" grep -q -- "$pattern" "$T/err.txt"
}
expect_exit2 "different sizes" "sizes differ: 16x12 and 8x8" "$T/a.exr" "$T/small.exr"
expect_exit2 "missing file" "$T/nothere.exr" "$T/a.exr" "$T/nothere.exr"
expect_exit2 "garbage file" "$T/garbage.exr" "$T/garbage.exr" "$T/a.exr"
expect_exit2 "even blur" "--blur" "$T/a.exr" "$T/b.exr" --blur 4
expect_exit2 "bad white" "--white-y" "$T/a.exr" "$T/b.exr" --white-y -1
expect_exit2 "heat map directory missing" "does not exist" "$T/a.exr" "$T/b.exr" --heatmap "$T/no/h.png"
expect_exit2 "unknown option" "unknown option" "$T/a.exr" "$T/b.exr" --frobnicate
expect_exit2 "one image" "two images" "$T/a.exr"

"$BIN" compare --help > "$T/help.txt"
check "--help exits 0" test $? -eq 0
check "--help names --white-y" grep -q -- "--white-y" "$T/help.txt"

finish
