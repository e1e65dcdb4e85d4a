# Shared prelude of the shell tests (sourced, not run): the binary from $1,
# the data root, a scratch directory removed on exit, and pass/fail counting
# that ends with the "N passed, N failed" line ctest's log shows.
set -u
BIN=${1:?usage: bash tests/cli_NAME.sh /path/to/specmip}
HERE=$(cd "$(dirname "${BASH_SOURCE[1]}")" && pwd)
ROOT=$(dirname "$HERE")
export SPECMIP_DATA=${SPECMIP_DATA:-$ROOT}
DATA=$SPECMIP_DATA
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
check() {  # check WHAT COMMAND...: counts COMMAND's success
    local what=$1; shift
    if "$@"; then ok; else bad "$what"; fi
}
# is_num X: X is one decimal number (not empty, not null, not a word): the
# figures a test compares must be there before any comparison can pass.
is_num() { [[ $1 =~ ^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$ ]]; }
# num A OP B: the numeric comparison A OP B (OP: < <= > >= == !=), false
# unless both sides are numbers (awk alone would compare "" or "null" as text).
num() {
    is_num "$1" && is_num "$3" || { echo "  not a number: '$1' $2 '$3'" >&2; return 1; }
    awk -v a="$1" -v b="$3" "BEGIN { exit !(a $2 b) }"
}
# near A B TOL: |A - B| <= TOL, all three numbers.
near() {
    is_num "$1" && is_num "$2" && is_num "$3" || { echo "  not a number: '$1' '$2' '$3'" >&2; return 1; }
    awk -v a="$1" -v b="$2" -v t="$3" 'BEGIN { d = a - b; exit !(d <= t && -d <= t) }'
}
# jnum FILE FILTER: prints the value of jq FILTER in FILE if it is a number
# (jq's type == "number"); otherwise prints "not-a-number" (which num and
# near refuse), says why on stderr and fails.
jnum() {
    local v
    if v=$(jq -e "($2) | if type == \"number\" then . else error(\"\\(type), not a number\") end" \
            "$1" 2>&1); then
        echo "$v"
    else
        echo "  $1: $2: ${v:-no value}" >&2
        echo not-a-number
        return 1
    fi
}
# same_pixels A B: both images read and every pixel value equal (idiff with
# no tolerance; oiiotool --diff would let differences of 1e-6 pass).
same_pixels() { idiff -fail 0 -warn 0 "$1" "$2" > /dev/null 2>&1; }
# other_pixels A B: both images read and some pixel differs (idiff's exit 2;
# a missing or unreadable file is 4, a size mismatch 3: neither counts).
other_pixels() {
    idiff -fail 0 -warn 0 "$1" "$2" > /dev/null 2>&1
    [ $? -eq 2 ]
}
# relavg A B [OPS...]: the largest channel's mean of |A - B| / (A + B + 1e-3)
# after OPS (kernel against reference); beyond A B: with a threshold as OPS,
# the share of pixel channels whose relative difference exceeds 1e-3.
relavg() {
    oiiotool "$1" "$2" --absdiff "$1" "$2" --add --addc 1e-3 --div "${@:3}" --printstats 2>&1 |
        sed -n 's/.*Stats Avg: *//p' | head -1 | awk '{m=$1; for (i=2;i<=NF;i++) if ($i>m) m=$i; print m}'
}
beyond() { relavg "$1" "$2" --subc 1e-3 --clamp:min=0 --mulc 1e30 --clamp:max=1; }
# lit_window IMG X Y: the 3 x 3 pixels from (X, Y) each have a positive
# channel sum (a light render's pixel words: pixel 65535 once meant "no splat").
lit_window() {
    oiiotool "$1" --cut "3x3+$2+$3" -o "$T/window.exr" > /dev/null 2>&1 &&
        oiiotool --dumpdata "$T/window.exr" |
        awk '/Pixel/ { n++; if ($(NF - 2) + $(NF - 1) + $NF > 0) lit++ } END { exit !(n == 9 && lit == 9) }'
}
# below A B: A is a number and A <= B
below() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a != "" && a + 0 <= b + 0) }'; }
# split_invariant ARGS...: specmip ARGS on PoCL's first device and on both
# (pthread, basic; SPECMIP_TEST_MEET: they meet at their first pass): each
# device renders a pass, and the two give the pixels of one, bit for bit.
split_invariant() {
    POCL_DEVICES="pthread basic" "$BIN" "$@" --device 0 -o "$T/one.exr"
    check "one device: exit 0" test $? -eq 0
    SPECMIP_TEST_MEET=2 POCL_DEVICES="pthread basic" "$BIN" "$@" --device all --json \
        -o "$T/two.exr" > "$T/two.json"
    check "two devices: exit 0" test $? -eq 0
    check "two devices: each rendered a pass" \
        test "$(jq '[.devices[] | select(.passes >= 1)] | length' "$T/two.json")" = 2
    check "two devices: the pixels of one, bit for bit" same_pixels "$T/one.exr" "$T/two.exr"
}
# skip REASON: the whole test cannot run here; ctest shows it as skipped
# (SKIP_RETURN_CODE 77 in tests/CMakeLists.txt).
skip() {
    echo "SKIP: $*"
    exit 77
}
# rendering PID ERR: true once the render PID has finished a pass (its
# --progress line in ERR), false if it ends first or 60 s go by.
rendering() {
    local i
    for i in $(seq 600); do
        grep -q "pass [1-9][0-9]*/" "$2" 2>/dev/null && return 0
        kill -0 "$1" 2>/dev/null || return 1
        sleep 0.1
    done
    return 1
}
# finish: the closing line; a test that checked nothing has not passed.
finish() {
    echo "$pass passed, $fail failed"
    [ "$pass" -gt 0 ] || echo "FAIL: no check ran" >&2
    [ "$fail" -eq 0 ] && [ "$pass" -gt 0 ]
}
