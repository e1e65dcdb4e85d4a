#!/bin/bash
# specmip render --film / --resume under mpirun with 2 ranks: 8 spp kept, then
# resumed to 16, is bit for bit one process's render to 16, whichever of one
# process or two ranks rendered each part (the passes are added in pass order
# on rank 0, whatever rank rendered them); a resume of another mode is
# refused by rank 0 (exit 2) and the film left as it was.
source "$(dirname "$0")/lib_cli.sh"
source "$(dirname "$0")/lib_mpi.sh"
film_samples() { grep -a -m1 '^samples=' "$1" | cut -d= -f2; }

# 128x128: 4 spp per pass, 8 spp ends on the pass grid and leaves 2 passes
# to share out, and the resume 2 more.
R=(render "$DATA/scenes/cornell_spiky.scene" --width 128 --height 128 --seed 3 --quiet)
"$BIN" "${R[@]}" --spp 16 -o "$T/one.exr"
check "one process, 16 spp: exit 0" test $? -eq 0

SPECMIP_TEST_MEET=2 "${MPI[@]}" -np 2 "$BIN" "${R[@]}" --spp 8 --film -o "$T/m.exr" --json \
    > "$T/m8.json" 2> "$T/m8.err"
check "2 ranks, 8 spp kept: exit 0" test $? -eq 0 -a "$(film_samples "$T/m.exr.film")" = 8
check "2 ranks, 8 spp: both ranks rendered" \
    test "$(jq '[.devices[] | select(.passes >= 1)] | length' "$T/m8.json")" = 2
SPECMIP_TEST_MEET=2 "${MPI[@]}" -np 2 "$BIN" "${R[@]}" --spp 16 --resume "$T/m.exr" --json \
    > "$T/m16.json" 2> "$T/m16.err"
check "2 ranks, resumed to 16: exit 0" test $? -eq 0
check "2 ranks, resumed to 16: both ranks rendered" \
    test "$(jq '[.devices[] | select(.passes >= 1)] | length' "$T/m16.json")" = 2
check "2 ranks: bit for bit one process's 16 spp" same_pixels "$T/one.exr" "$T/m.exr"

# Kept by one process, resumed by two ranks.
"$BIN" "${R[@]}" --spp 8 --film -o "$T/p.exr"
"${MPI[@]}" -np 2 "$BIN" "${R[@]}" --spp 16 --resume "$T/p.exr" 2> "$T/p.err"
check "one process then 2 ranks: exit 0" test $? -eq 0
check "one process then 2 ranks: bit for bit" same_pixels "$T/one.exr" "$T/p.exr"

# Another mode: refused, the film untouched.
cp "$T/m.exr.film" "$T/keep.film"
"${MPI[@]}" -np 2 "$BIN" "${R[@]}" --spp 24 --mode truth --resume "$T/m.exr" 2> "$T/bad.err"
check "2 ranks, another mode: refused" test $? -eq 2
check "2 ranks, another mode: says so" grep -q "mode ml (this render: truth)" "$T/bad.err"
check "2 ranks, another mode: film untouched" cmp -s "$T/m.exr.film" "$T/keep.film"
finish
