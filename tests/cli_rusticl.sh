#!/bin/bash
# Every mode on Mesa's Rusticl (RUSTICL_ENABLE=llvmpipe: a CPU device on a
# second OpenCL platform, with its own compiler) renders and gives PoCL's
# image within the tolerance between two OpenCL compilers. Rusticl reports no
# profiling times; the render must not mind.
source "$(dirname "$0")/lib_cli.sh"
source "$HERE/lib_platforms.sh"
export RUSTICL_ENABLE=llvmpipe

pocl=$(platform_device "Portable Computing Language")
rus=$(platform_device rusticl)
check "a PoCL device" test -n "$pocl"
check "a Rusticl device (mesa-opencl-icd, RUSTICL_ENABLE=llvmpipe)" test -n "$rus"
[ -n "$pocl" ] && [ -n "$rus" ] || { finish; exit; }

R=(--width 48 --height 36 --spp 4 --seed 9 --quiet)
for run in "${RUNS[@]}"; do
    set -- $run
    mode=$1; shift
    name="$mode $(basename "$1" .scene)${2:+ $2 $3}"
    "$BIN" render "$@" --mode "$mode" "${R[@]}" --device "$pocl" -o "$T/p.exr"
    check "$name: PoCL renders" test $? -eq 0
    "$BIN" render "$@" --mode "$mode" "${R[@]}" --device "$rus" --json -o "$T/r.exr" \
        > "$T/r.json" 2> "$T/r.err"
    rc=$?
    check "$name: Rusticl renders (exit $rc)" test $rc -eq 0
    [ $rc -eq 0 ] || { cat "$T/r.err" >&2; continue; }
    check "$name: Rusticl did every path" \
        jq -e '.devices | length == 1 and (.[0].name | test("llvmpipe")) and .[0].paths == 48 * 36 * 4' \
        "$T/r.json" > /dev/null
    close_images "$name: Rusticl vs PoCL" "$T/p.exr" "$T/r.exr"
done
finish
