#!/bin/bash
# specmip render --integrator light on the OpenCL backend under mpirun: two
# ranks give the one process's pixels bit for bit (each pass's splats summed
# in fixed point on the device that renders it, the pass images added in pass
# order), every rank taking passes; rank 1's command line asks for the path
# integrator, which rank 0's overrides. The CPU reference's case is cli_mpi.sh's.
source "$(dirname "$0")/lib_cli.sh"
MPI=(mpirun --allow-run-as-root --oversubscribe)
# 48 x 48 at 87 spp: three passes of 29 spp; the ranks meet at their first pass.
LR=(render "$DATA/scenes/cornell_spiky.scene" --mode ml --width 48 --height 48 --spp 87 --seed 3 --quiet)
"$BIN" "${LR[@]}" --integrator light -o "$T/one.exr"
check "light, one process: exit 0" test $? -eq 0
SPECMIP_TEST_MEET=2 "${MPI[@]}" -np 1 "$BIN" "${LR[@]}" --integrator light --json \
    -o "$T/two.exr" : -np 1 "$BIN" "${LR[@]}" > "$T/two.json" 2> "$T/two.err"
check "light, -np 2: exit 0" test $? -eq 0
check "light, -np 2: same EXR as one process" same_pixels "$T/one.exr" "$T/two.exr"
check "light, -np 2: every rank took passes" \
    test "$(jq '[.devices[] | select(.passes >= 1)] | length' "$T/two.json")" = 2
finish
