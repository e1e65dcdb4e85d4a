#!/bin/bash
# specmip render on several OpenCL devices (PoCL's POCL_DEVICES makes them):
# the same EXR as one device (bit for bit for devices of one kind), per-device
# statistics in which each device did work, an injected device failure
# (SPECMIP_CL_FAIL) that the others absorb, all devices failing (exit 1,
# existing output untouched), bad --device, an interruption stopping both
# devices inside their passes.
source "$(dirname "$0")/lib_cli.sh"
source "$(dirname "$0")/lib_platforms.sh"
# every_device_worked JSON N: N devices in --json stats, each with passes and paths.
# The renders it checks meet at their first pass (SPECMIP_TEST_MEET, render_run.h):
# on a loaded machine the device that comes up first could otherwise take all
# four passes before the other one asks.
every_device_worked() {
    test "$(jq '.devices | length' "$1")" = "$2" &&
        test "$(jq '[.devices[] | select(.passes >= 1 and .paths > 0)] | length' "$1")" = "$2"
}

# 128x96 at 24 spp: 6 spp per pass (spm_spp_per_pass), 4 passes to share out.
R=(render --width 128 --height 96 --spp 24 --seed 3 --quiet)
BB="basic basic"

POCL_DEVICES=$BB "$BIN" "${R[@]}" --device 0 -o "$T/one.exr" 2> "$T/one.err"
check "one device: exit 0" test $? -eq 0
SPECMIP_TEST_MEET=2 POCL_DEVICES=$BB "$BIN" "${R[@]}" --device all --json -o "$T/two.exr" > "$T/two.json" 2> "$T/two.err"
check "two devices: exit 0" test $? -eq 0
check "two devices: same EXR as one device" same_pixels "$T/one.exr" "$T/two.exr"
check "json: two devices" test "$(jq '.devices | length' "$T/two.json")" = 2
check "json: every path counted" test "$(jq '[.devices[].paths] | add' "$T/two.json")" = $((128 * 96 * 24))
check "json: shares add up to 1" near "$(jnum "$T/two.json" '[.devices[].share] | add')" 1 1e-3
check "json: 4 passes in all" test "$(jq '[.devices[].passes] | add' "$T/two.json")" = 4
check "json: device names" test "$(jq -r '.devices[0].name' "$T/two.json" | grep -c basic)" = 1
check "json: each device rendered passes" every_device_worked "$T/two.json" 2
SPECMIP_TEST_MEET=2 POCL_DEVICES=$BB "$BIN" "${R[@]}" --device 1,0 --stats -o "$T/list.exr" > "$T/list.txt"
check "--device 1,0: exit 0" test $? -eq 0
check "--device 1,0: same EXR" same_pixels "$T/one.exr" "$T/list.exr"
check "--stats: a line per device" test "$(grep -c '^device [01] .*Mpaths/s' "$T/list.txt")" = 2
check "--stats: each device rendered passes" \
    test "$(grep -c '^device [01] .*: [1-9][0-9]* paths .* in [1-9][0-9]* passes' "$T/list.txt")" = 2

# A scene whose paths take several levels: every pass launches the shade
# kernels over buckets of varying size, concurrently on both devices (PoCL
# shares compiled kernels between devices whose programs are identical); at
# 20 spp the last pass is smaller (2 spp) than the others.
SPIKY=${SPECMIP_DATA:-.}/scenes/cornell_spiky.scene
POCL_DEVICES=$BB "$BIN" "${R[@]}" "$SPIKY" --spp 20 --device 0 -o "$T/spiky1.exr"
check "levels, one device: exit 0" test $? -eq 0
SPECMIP_TEST_MEET=2 POCL_DEVICES=$BB "$BIN" "${R[@]}" "$SPIKY" --spp 20 --device all --json -o "$T/spiky2.exr" \
    > "$T/spiky2.json" 2> "$T/spiky2.err"
check "levels, two devices: exit 0" test $? -eq 0
check "levels, two devices: each device rendered passes" every_device_worked "$T/spiky2.json" 2
check "levels, two devices: same EXR as one device" same_pixels "$T/spiky1.exr" "$T/spiky2.exr"

# Device 1 fails on its first pass: reported by name, device 0 renders it all.
SPECMIP_CL_FAIL=1:0 POCL_DEVICES=$BB "$BIN" "${R[@]}" --device all --json -o "$T/fail1.exr" \
    > "$T/fail1.json" 2> "$T/fail1.err"
check "one device failing: exit 0" test $? -eq 0
check "failure names the device" grep -q "device '1: basic.*failed" "$T/fail1.err"
check "json: device 1 failed" test "$(jq '.devices[1].failed' "$T/fail1.json")" = true
check "json: device 0 rendered all 4 passes" test "$(jq -c '[.devices[].passes]' "$T/fail1.json")" = "[4,0]"
check "one device failing: same EXR" same_pixels "$T/one.exr" "$T/fail1.exr"

# The only device fails on its third pass: exit 1, and the render is not what
# was asked for, so an existing output stays as it was (and none is created).
echo old > "$T/dead.exr"
SPECMIP_CL_FAIL=0:2 POCL_DEVICES=$BB "$BIN" "${R[@]}" --device 0 -o "$T/dead.exr" -o "$T/dead.png" \
    2> "$T/dead.err"
check "all devices failing: exit 1" test $? -eq 1
check "all devices failing: says so" grep -q "every device failed; 2 of 4 passes.*no image written" "$T/dead.err"
check "all devices failing: existing output untouched" test "$(cat "$T/dead.exr")" = old
check "all devices failing: no new output" test ! -e "$T/dead.png"

# Interrupted with both devices inside a pass (1024x768 at 2 spp: two passes
# of three batches; the test hook holds each device at its first batch
# boundary): both stop there, nothing is written.
echo old > "$T/int.exr"
SPECMIP_TEST_PAUSE=pass:1,pass:2 POCL_DEVICES=$BB "$BIN" render --width 1024 --height 768 --spp 2 \
    --device all --quiet -o "$T/int.exr" 2> "$T/int.err" &
pid=$!
for ((i = 0; i < 600; i++)); do
    [ "$(grep -c "test pause at pass" "$T/int.err")" -ge 2 ] && break
    kill -0 $pid 2> /dev/null || break
    sleep 0.1
done
kill -INT $pid
wait $pid
check "two devices interrupted: exit 130" test $? -eq 130
check "two devices interrupted: nothing written" test "$(cat "$T/int.exr")" = old
check "two devices interrupted: says so" grep -q "interrupted in the first pass" "$T/int.err"

# Bad --device values: exit 2 with a message, nothing rendered.
for bad in 0,0 7 0,x 0, ""; do
    POCL_DEVICES=$BB "$BIN" "${R[@]}" --device "$bad" -o "$T/bad.exr" 2> "$T/bad.err"
    check "--device '$bad': exit 2" test $? -eq 2
    check "--device '$bad': message" grep -q "device" "$T/bad.err"
done
check "bad --device: no image" test ! -e "$T/bad.exr"

# Different kinds: only compiler floating point may differ. A split that lost
# or repeated a pass would differ by the noise of 24 spp (several dE00); the
# rare path flipped by a last-bit difference (test_multidevice_mixed: <= 1e-3
# of paths) moves the blurred mean dE00 by far less than 0.1.
PB="pthread basic"
pth=$(POCL_DEVICES=$PB "$BIN" devices | grep -m1 'device [0-9]*: pthread' | sed 's/ *device \([0-9]*\):.*/\1/')
check "pthread device found" is_num "$pth"
POCL_DEVICES=$PB "$BIN" "${R[@]}" --device "$pth" -o "$T/pth.exr"
check "pthread alone: exit 0" test $? -eq 0
SPECMIP_TEST_MEET=2 POCL_DEVICES=$PB "$BIN" "${R[@]}" --device all --json -o "$T/mixed.exr" > "$T/mixed-run.json"
check "pthread + basic: exit 0" test $? -eq 0
check "pthread + basic: each device rendered passes" every_device_worked "$T/mixed-run.json" 2
close_images "pthread + basic against pthread alone" "$T/pth.exr" "$T/mixed.exr"

finish
