#!/usr/bin/env bash
# A spectral film too large for this machine's memory is refused before
# rendering, on both backends, naming the image, its bins and the memory it
# needs; a small image of the same bins is not refused. The
# image is sized to the machine: 1 nm bins keep 400 doubles a pixel in the
# film, so a square of side S needs more than 3200 S² bytes.
source "$(dirname "$0")/lib_cli.sh"
source "$(dirname "$0")/lib_spectral.sh"
mem_kb=$(awk '/^MemTotal:/ { print $2 }' /proc/meminfo)
check "MemTotal read" is_num "$mem_kb"
# the smallest multiple of 64 with 3200 S² >= 1.25 x the memory
S=$(awk -v m="$mem_kb" 'BEGIN { s = sqrt(1.25 * m * 1024 / 3200); s = 64 * int(s / 64 + 1); print s }')
MAX=16384 # the largest image side (render --help)
if ! num "$S" '<=' $MAX; then
    skip "this machine's $((mem_kb / 1024 / 1024)) GB hold a ${MAX}x${MAX} film of 400 bins"
fi
echo "  ${S}x${S} at 1 nm: $(awk -v s="$S" 'BEGIN { printf "%.0f", 3200 * s * s / 1e9 }') GB of film sums"
refused() {  # refused WHAT ARGS...: exit 2 before rendering, the message, no file
    local what=$1
    shift
    rm -f "$T"/r.*
    timeout 60 "$BIN" render "$SCENE" --spp 2 --quiet --mode truth --width "$S" --height "$S" \
        -o "$T/r.spectral.exr" "$@" 2> "$T/err"
    local rc=$?
    check "$what: exit 2 (got $rc)" test $rc -eq 2
    check "$what: names the image, its bins and the memory" \
        grep -q "${S}x${S} spectral image of 400 bins needs .* GB of host memory" "$T/err"
    check "$what: nothing written" test -z "$(ls "$T"/r.* 2> /dev/null)"
}
refused "1 nm, CPU reference" --spectral-nm 1 --backend cpu
refused "1 nm, OpenCL" --spectral-nm 1
# The refusal is of the size: the same render at 64x64 goes through.
"$BIN" render "$SCENE" --spp 1 --mode truth --spectral-nm 1 --width 64 --height 64 \
    -o "$T/small.spectral.exr" --quiet 2> "$T/err"
rc=$?
check "1 nm at 64x64: exit 0 (got $rc)" test $rc -eq 0 -a -s "$T/small.spectral.exr"
finish
