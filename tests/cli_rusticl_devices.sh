#!/bin/bash
# Devices on two OpenCL platforms, PoCL and Mesa's Rusticl (llvmpipe): the
# numbering does not depend on the ICD loader's order (PoCL's CPU device stays
# device 0), '--device all' leaves out a second platform's CPU device, and an
# explicit PoCL + Rusticl render gives the PoCL image within the tolerance
# between two compilers with both devices doing passes.
source "$(dirname "$0")/lib_cli.sh"
source "$HERE/lib_platforms.sh"
export RUSTICL_ENABLE=llvmpipe

pocl=$(platform_device "Portable Computing Language")
rus=$(platform_device rusticl)
check "PoCL's device is device 0" test "$pocl" = 0
check "a Rusticl device (mesa-opencl-icd, RUSTICL_ENABLE=llvmpipe)" test -n "$rus"
[ -n "$rus" ] || { finish; exit; }

# The loader lists platforms in the order it reads its vendor files (ocl-icd:
# the directory's order, only GPU-rich platforms moved first). Vendor files
# in a scratch directory, renamed until the directory lists Rusticl's first;
# the loader then puts Rusticl first, specmip still numbers PoCL's device 0.
pocl_lib=$(sed -n 1p /etc/OpenCL/vendors/pocl.icd)
rus_lib=$(sed -n 1p /etc/OpenCL/vendors/rusticl.icd)
V=$T/vendors
for i in $(seq 32); do
    rm -rf "$V"; mkdir "$V"
    echo "$pocl_lib" > "$V/p$i.icd"
    echo "$rus_lib" > "$V/r$i.icd"
    [ "$(ls -f "$V" | grep -m1 '\.icd$')" = "r$i.icd" ] && break
done
first=$(OCL_ICD_VENDORS=$V clinfo -l | sed -n 's/^Platform #0: //p')
check "loader lists Rusticl first (got '$first'; else this proves nothing)" test "$first" = rusticl
OCL_ICD_VENDORS=$V "$BIN" devices > "$T/devices.txt"
check "Rusticl first in the loader: devices exits 0" test $? -eq 0
check "Rusticl first in the loader: PoCL still platform 0" \
    grep -q '^platform 0: Portable Computing Language' "$T/devices.txt"
check "Rusticl first in the loader: PoCL's device still device 0" \
    test "$(grep -m1 '^  device 0:' "$T/devices.txt" | grep -c llvmpipe)" = 0

R=(--width 64 --height 48 --seed 5 --quiet --json)
OCL_ICD_VENDORS=$V "$BIN" render "${R[@]}" --spp 1 --device 0 -o "$T/d0.exr" > "$T/d0.json"
check "--device 0, Rusticl first: exit 0" test $? -eq 0
check "--device 0 renders on PoCL whatever the loader's order" \
    jq -e '.devices[0].name | test("llvmpipe") | not' "$T/d0.json" > /dev/null

# all: PoCL's devices, not the second platform's CPU device.
"$BIN" render "${R[@]}" --spp 1 --device all -o "$T/all.exr" > "$T/all.json"
check "--device all: exit 0" test $? -eq 0
check "--device all: PoCL only" \
    jq -e '[.devices[].name] | length == 1 and (.[0] | test("llvmpipe") | not)' "$T/all.json" > /dev/null
POCL_DEVICES="basic basic" "$BIN" render "${R[@]}" --spp 1 --device all -o "$T/all2.exr" > "$T/all2.json"
check "--device all, two PoCL devices: exit 0" test $? -eq 0
check "--device all: both PoCL devices, not Rusticl's" \
    jq -e '[.devices[].name | test("^[01]: basic")] == [true, true]' "$T/all2.json" > /dev/null
"$BIN" devices | grep -A4 "device $rus: llvmpipe" > "$T/rus.txt"
check "devices: says Rusticl's device is not in all" grep -q "not in --device all" "$T/rus.txt"

# PoCL + Rusticl. 128x128 at 24 spp: 4 spp per pass (spm_spp_per_pass), 6
# passes; the devices meet at their first pass (SPECMIP_TEST_MEET), so both
# render however long Rusticl takes to come up.
R=(--width 128 --height 128 --spp 24 --seed 5 --quiet --json)
"$BIN" render "${R[@]}" --device "$pocl" -o "$T/one.exr" > "$T/one.json"
check "PoCL alone: exit 0" test $? -eq 0
SPECMIP_TEST_MEET=2 "$BIN" render "${R[@]}" --device "$pocl,$rus" -o "$T/two.exr" > "$T/two.json" 2> "$T/two.err"
rc=$?
check "PoCL + Rusticl: exit 0 (got $rc)" test $rc -eq 0
[ $rc -eq 0 ] || cat "$T/two.err" >&2
echo "passes by device: $(jq -c '[.devices[] | {name, passes}]' "$T/two.json")"
check "PoCL + Rusticl: two devices, each did passes, 6 in all" \
    jq -e '(.devices | length) == 2 and all(.devices[]; .passes > 0 and .paths > 0 and (.failed | not))
           and ([.devices[].passes] | add) == 6 and .passes == 6' "$T/two.json" > /dev/null
check "PoCL + Rusticl: Rusticl was one of them" \
    jq -e 'any(.devices[]; .name | test("llvmpipe"))' "$T/two.json" > /dev/null
close_images "PoCL + Rusticl vs PoCL alone" "$T/one.exr" "$T/two.exr"
finish
