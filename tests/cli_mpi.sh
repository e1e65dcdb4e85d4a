#!/bin/bash
# specmip render under mpirun with 2 and 3 ranks on one machine: the same EXR
# as one process (bit for bit: every rank runs the same kind of device), only
# rank 0 reading the scene (the others refuse every scene file), the dynamic
# split (a rank made slow takes fewer passes, every rank takes some), rank 0's
# mode and seed whatever another rank's command line says, a killed rank
# (existing output untouched, no temporary file left, the rank named), and
# SIGTERM to mpirun (rank 0 writes the passes done in order, every rank exits 130).
source "$(dirname "$0")/lib_cli.sh"
source "$(dirname "$0")/lib_mpi.sh"
# rank_pid MPIRUN_PID RANK: the PID of that rank (a child of mpirun on this machine)
rank_pid() {
    local c
    for c in $(pgrep -P "$1"); do
        tr '\0' '\n' < "/proc/$c/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$2" &&
            echo "$c" && return 0
    done
    return 1
}
not_grep() { ! grep -q "$1" "$2"; }
no_temp_files() { [ -z "$(ls -A "$1" | grep -v '^out\.exr$')" ]; }

# 128x96 at 48 spp: 6 spp per pass (spm_spp_per_pass), 8 passes to share out.
SPIKY=$DATA/scenes/cornell_spiky.scene
R=(render "$SPIKY" --width 128 --height 96 --spp 48 --seed 3 --quiet)
"$BIN" "${R[@]}" -o "$T/one.exr"
check "one process: exit 0" test $? -eq 0
for np in 2 3; do
    SPECMIP_TEST_REFUSE_SCENE_FILES=others "${MPI[@]}" -np $np "$BIN" "${R[@]}" --json \
        -o "$T/np$np.exr" > "$T/np$np.json" 2> "$T/np$np.err"
    check "-np $np: exit 0" test $? -eq 0
    check "-np $np: same EXR as one process" same_pixels "$T/one.exr" "$T/np$np.exr"
    check "-np $np: no rank opened a scene file" not_grep "refuses to open" "$T/np$np.err"
    check "-np $np: a device per rank in --json" \
        test "$(jq '[.devices[].name | select(test("^rank [0-9]+ "))] | length' "$T/np$np.json")" = $np
    check "-np $np: every path counted" \
        test "$(jq '[.devices[].paths] | add' "$T/np$np.json")" = $((128 * 96 * 48))
    check "-np $np: 8 passes in all" test "$(jq '[.devices[].passes] | add' "$T/np$np.json")" = 8
done

# A spectral output is refused under mpirun (exit 2 from every rank), nothing written.
"${MPI[@]}" -np 2 "$BIN" "${R[@]}" -o "$T/sp.exr" -o "$T/sp.spectral.exr" 2> "$T/sp.err"
check "spectral under mpirun: refused" test $? -ne 0
check "spectral under mpirun: says so" grep -q "spectral.exr output is not supported under mpirun" "$T/sp.err"
check "spectral under mpirun: nothing written" test ! -e "$T/sp.exr" -a ! -e "$T/sp.spectral.exr"
# The hook bites: a process that refuses scene files cannot render this scene.
SPECMIP_TEST_REFUSE_SCENE_FILES=all "$BIN" "${R[@]}" -o "$T/refused.exr" 2> "$T/refused.err"
check "refusing hook: the render fails (exit 2)" test $? -eq 2
check "refusing hook: says so" grep -q "rank 0 refuses to open .*cornell_spiky.scene" "$T/refused.err"

# The light integrator (the CPU reference, splats summed per chunk in fixed
# point): two ranks give the one process's pixels bit for bit; rank 1's own
# command line asks for the path integrator, which rank 0's overrides. 64x48
# at 84 spp: 21 spp per pass, 4 passes; the ranks meet at their first pass.
LR=(render "$DATA/scenes/cornell.scene" --backend cpu --width 64 --height 48 --spp 84 --seed 3 --quiet)
"$BIN" "${LR[@]}" --integrator light -o "$T/light1.exr"
check "light, one process: exit 0" test $? -eq 0
SPECMIP_TEST_MEET=2 "${MPI[@]}" -np 1 "$BIN" "${LR[@]}" --integrator light --json \
    -o "$T/light2.exr" : -np 1 "$BIN" "${LR[@]}" > "$T/light2.json" 2> "$T/light2.err"
check "light, -np 2: exit 0" test $? -eq 0
check "light, -np 2: same EXR as one process" same_pixels "$T/light1.exr" "$T/light2.exr"
check "light, -np 2: every rank took passes" \
    test "$(jq '[.devices[] | select(.passes >= 1)] | length' "$T/light2.json")" = 2

# Dynamic split: rank 2 waits 2 s after each pass (longer than a pass of the
# others takes even with three ranks on two loaded cores); its own command line
# asks for another mode and seed, which rank 0's override. The ranks meet at
# their first pass (SPECMIP_TEST_MEET), so each takes one whatever the load.
R2=(render "$SPIKY" --width 128 --height 96 --spp 96 --seed 3 --quiet)
"$BIN" "${R2[@]}" -o "$T/one96.exr"
check "one process, 96 spp: exit 0" test $? -eq 0
SPECMIP_TEST_MEET=3 "${MPI[@]}" -np 2 "$BIN" "${R2[@]}" --json -o "$T/slow.exr" : \
    -np 1 env SPECMIP_TEST_SLOW_PASS=2 "$BIN" "${R2[@]}" --mode rgb --seed 9 \
    > "$T/slow.json" 2> "$T/slow.err"
check "slow rank: exit 0" test $? -eq 0
check "slow rank: same EXR as one process" same_pixels "$T/one96.exr" "$T/slow.exr"
p0=$(jq '.devices[] | select(.name | startswith("rank 0 ")) | .passes' "$T/slow.json")
p1=$(jq '.devices[] | select(.name | startswith("rank 1 ")) | .passes' "$T/slow.json")
p2=$(jq '.devices[] | select(.name | startswith("rank 2 ")) | .passes' "$T/slow.json")
every_rank_took() { num "$p0" '>=' 1 && num "$p1" '>=' 1 && num "$p2" '>=' 1; }
slow_took_fewer() { num "$p2" '<' "$p0" && num "$p2" '<' "$p1"; }
check "slow rank: every rank took passes ($p0 $p1 $p2)" every_rank_took
check "slow rank: it took fewer than each other rank ($p0 $p1 $p2)" slow_took_fewer

# Long renders for the fault and the signal: 2 spp per pass, 512 passes.
LONG=(render --width 256 --height 192 --spp 1024 --progress)
# A killed rank: mpirun ends the job; the existing output stays as it was.
mkdir "$T/kill" && echo old > "$T/kill/out.exr"
"${MPI[@]}" --mca odls_base_sigkill_timeout 10 -np 3 "$BIN" "${LONG[@]}" -o "$T/kill/out.exr" \
    2> "$T/kill.err" &
mp=$!
check "killed rank: rendering" rendering $mp "$T/kill.err"
r1=$(rank_pid $mp 1) && kill -KILL "$r1"
wait $mp
check "killed rank: mpirun fails" test $? -ne 0
check "killed rank: existing output untouched" test "$(cat "$T/kill/out.exr")" = old
check "killed rank: no temporary file left" no_temp_files "$T/kill"
check "killed rank: rank 0 names it" grep -q "rank 1 stopped without a signal.*no image written" "$T/kill.err" ||
    grep -v "^$" "$T/kill.err" | tail -5 >&2
check "killed rank: mpirun names it" grep -q "process rank 1 .*signal 9" "$T/kill.err"

# SIGTERM to every rank, as mpirun forwards it: rank 0 writes the image of the
# passes added so far and says so, and every rank exits 130 (mpirun's own exit
# code is 1). The signal goes to the ranks themselves: when mpirun gets it,
# whether and when it passes it on depends on OpenMPI's launch state and its
# grace before SIGKILL (seen here: forwarded at once with the default second
# of grace, not at all with --mca odls_base_sigkill_timeout 30), which is
# OpenMPI's behaviour, not specmip's. A wrapper records each rank's exit code.
cat > "$T/rc_of.py" << 'PY'
import os, signal, subprocess, sys
p = subprocess.Popen(sys.argv[2:])
signal.signal(signal.SIGTERM, lambda s, f: None)
rc = p.wait()
rc = rc if rc >= 0 else 128 - rc
open("%s.%s" % (sys.argv[1], os.environ["OMPI_COMM_WORLD_RANK"]), "w").write("%d\n" % rc)
sys.exit(rc)
PY
"${MPI[@]}" -np 2 python3 "$T/rc_of.py" "$T/rc" "$BIN" "${LONG[@]}" -o "$T/sig.exr" 2> "$T/sig.err" &
mp=$!
check "signal: rendering" rendering $mp "$T/sig.err"
ranks=()
for r in 0 1; do
    w=$(rank_pid $mp $r) && ranks+=($(pgrep -P "$w"))
done
check "signal: both ranks found (${ranks[*]})" test ${#ranks[@]} -eq 2
kill -TERM "${ranks[@]}"
wait $mp
check "signal: rank 0 wrote the image" \
    grep -q "interrupted after [0-9]* of 1024 samples per pixel; image written" "$T/sig.err"
spp=$(oiiotool --info -v "$T/sig.exr" 2>/dev/null | sed -n 's/^ *samplesPerPixel: //p')
check "signal: the image records the passes done (spp $spp)" test "${spp:-0}" -ge 2 -a "${spp:-0}" -lt 1024
check "signal: rank 0 exits 130" test "$(cat "$T/rc.0" 2>/dev/null)" = 130
check "signal: rank 1 exits 130" test "$(cat "$T/rc.1" 2>/dev/null)" = 130
finish
