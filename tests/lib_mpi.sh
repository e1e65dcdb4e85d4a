# Shared by the tests that render under mpirun (tests/cli_mpi*.sh); sourced
# after lib_cli.sh.

# every rank on this machine, as root, more ranks than cores allowed
MPI=(mpirun --allow-run-as-root --oversubscribe)

# two_ranks_same INTEGRATOR RENDER-ARGS...: the render with --integrator
# INTEGRATOR in one process, then in two ranks that meet at their first pass
# (SPECMIP_TEST_MEET): rank 1's command line names no integrator, which rank
# 0's overrides. Both exit 0, the pixels are one process's bit for bit, and
# every rank took passes.
two_ranks_same() {
    local integ=$1
    shift
    "$BIN" "$@" --integrator "$integ" -o "$T/one.exr"
    check "$integ, one process: exit 0" test $? -eq 0
    SPECMIP_TEST_MEET=2 "${MPI[@]}" -np 1 "$BIN" "$@" --integrator "$integ" --json \
        -o "$T/two.exr" : -np 1 "$BIN" "$@" > "$T/two.json" 2> "$T/two.err"
    check "$integ, -np 2: exit 0" test $? -eq 0
    check "$integ, -np 2: same EXR as one process" same_pixels "$T/one.exr" "$T/two.exr"
    check "$integ, -np 2: every rank took passes" \
        test "$(jq '[.devices[] | select(.passes >= 1)] | length' "$T/two.json")" = 2
}
