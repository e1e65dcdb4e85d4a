#!/bin/bash
# Mutation testing: each mutant of tools/mutants.txt is a plausible bug put
# into a copy of the tree; the tests the list names for it must fail.
#   caught    a named test failed (or timed out)
#   survived  every named test passed: no test sees the bug
#   stale     an edit no longer changes its file (the code moved): neither
#   unviable  the mutant does not build: neither
# Not part of ctest (a run takes the better part of an hour on 2 cores).
#
# usage: tools/mutants.sh [-j N] [-l LIST] [NAME_REGEX]
#   NAME_REGEX  run only the mutants whose name matches (grep -E)
#   -j N        build jobs (default 2)
#   -l LIST     the list (default tools/mutants.txt)
# The work directory, $TMPDIR/specmip-mutants (default /tmp), is kept and
# reused: a second run rebuilds only what changed.
# The copy holds the tree's tracked and untracked (not ignored) files; it is
# built once in its own build directory, then each mutant rebuilds only what
# its tests need (specmip for cli_* tests, the test's program for test_*).
# Kernels are compiled at run time from the copy (SPECMIP_DATA is the copy,
# as ctest sets it there), so a kernel mutant rebuilds nothing, and the
# contract check (host/opencl/cl_contract.c) sees the headers the copy's
# binary embeds, mutated or not.
set -u
ROOT=$(cd "$(dirname "$0")/.." && pwd)
LIST=$ROOT/tools/mutants.txt
JOBS=2 ONLY=
while [ $# -gt 0 ]; do
    case $1 in
    -j) JOBS=$2; shift ;;
    -l) LIST=$(realpath "$2"); shift ;;
    -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
    *) ONLY=$1 ;;
    esac
    shift
done
W=${TMPDIR:-/tmp}/specmip-mutants
TOUCHED=()
restore() {  # the mutated files back from the tree
    for f in "${TOUCHED[@]}"; do cp "$ROOT/$f" "$SRC/$f"; done
    TOUCHED=()
}
trap 'restore' EXIT
trap 'echo "interrupted" >&2; exit 130' INT TERM
SRC=$W/src BUILD=$W/build LOG=$W/logs
mkdir -p "$SRC" "$LOG"

# the copy: refreshed from the tree, a file only where it differs (a fresh
# mtime, so that make rebuilds it; the build directory is kept between runs)
(cd "$ROOT" && git ls-files -co --exclude-standard) | grep -v '^build' | while IFS= read -r f; do
    [ -f "$ROOT/$f" ] || continue
    cmp -s "$ROOT/$f" "$SRC/$f" && continue
    mkdir -p "$SRC/$(dirname "$f")" && cp "$ROOT/$f" "$SRC/$f" || exit 2
done || { echo "cannot copy the tree to $SRC" >&2; exit 2; }
# configured every run: the tests are found by glob (a new one needs a new target)
cmake -S "$SRC" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release > "$LOG/configure.log" 2>&1 ||
    { echo "configure failed: $LOG/configure.log" >&2; exit 2; }
# what the list's tests need: specmip for cli_* tests, each test_* program
targets_of() {  # targets_of TESTS...
    local t
    echo specmip
    for t in "$@"; do [[ $t == test_* ]] && echo "$t"; done
}
ALL=$(grep -v '^[[:space:]]*#' "$LIST" | awk -F' :: ' 'NF > 2 { print $2 }' | tr ' ' '\n' | sort -u)
echo "building the unmutated copy in $BUILD ..."
nice cmake --build "$BUILD" -j"$JOBS" --target $(targets_of $ALL | sort -u) > "$LOG/build.log" 2>&1 ||
    { echo "the unmutated copy does not build: $LOG/build.log" >&2; exit 2; }


caught=0 survived=0 stale=0 unviable=0
SURV=()
while IFS= read -r line; do
    [[ $line =~ ^[[:space:]]*(#|$) ]] && continue
    # NAME :: TESTS :: FILE => SED [:: FILE => SED]...
    name=$(sed 's/ *::.*//' <<< "$line")
    [ -n "$ONLY" ] && ! grep -qE "$ONLY" <<< "$name" && continue
    rest=${line#*:: }
    tests=${rest%% :: *}
    edits=${rest#* :: }
    status= why=
    while [ -n "$edits" ]; do
        one=${edits%% :: *}
        [ "$one" = "$edits" ] && edits= || edits=${edits#* :: }
        file=${one%% => *} expr=${one#* => }
        if [ ! -f "$SRC/$file" ]; then status=stale why="$file: no such file"; break; fi
        TOUCHED+=("$file")
        sed -i -e "$expr" "$SRC/$file" 2> "$LOG/$name.sed" ||
            { status=stale why="$file: sed: $(cat "$LOG/$name.sed")"; break; }
        if cmp -s "$ROOT/$file" "$SRC/$file"; then status=stale why="$file: $expr changes nothing"; break; fi
    done
    if [ -z "$status" ]; then
        if ! nice cmake --build "$BUILD" -j"$JOBS" --target $(targets_of $tests) > "$LOG/$name.build" 2>&1; then
            status=unviable why="does not build: $LOG/$name.build"
        else
            re="^($(tr ' ' '|' <<< "$tests"))\$"
            (cd "$BUILD" && nice ctest -R "$re" --timeout 600 > "$LOG/$name.test" 2>&1)
            rc=$?
            ran=$(grep -cE 'Test +#' "$LOG/$name.test")
            if [ "$ran" -ne "$(wc -w <<< "$tests")" ]; then
                status=unviable why="ran $ran of the tests '$tests' ($LOG/$name.test)"
            elif [ $rc -ne 0 ]; then
                status=caught why=$(grep -E '\*\*\*Failed|\*\*\*Timeout|Exception' "$LOG/$name.test" |
                                    sed -E 's/.*Test +#[0-9]+: ([^ ]+).*/\1/' | tr '\n' ' ')
            elif grep -q 'Not Run\|Skipped' "$LOG/$name.test"; then
                status=unviable why="a test skipped ($LOG/$name.test)"
            else
                status=survived
            fi
        fi
    fi
    restore
    case $status in
    caught) caught=$((caught + 1)) ;;
    survived) survived=$((survived + 1)); SURV+=("$name") ;;
    stale) stale=$((stale + 1)) ;;
    unviable) unviable=$((unviable + 1)) ;;
    esac
    printf '%-9s %-28s %s\n' "$status" "$name" "$why"
done < "$LIST"
total=$((caught + survived))
echo "caught $caught, survived $survived, stale $stale, unviable $unviable" \
     "(score $caught/$total$([ $total -gt 0 ] && awk -v c=$caught -v t=$total 'BEGIN { printf " = %.0f %%", 100 * c / t }'))"
[ ${#SURV[@]} -eq 0 ] || echo "survivors: ${SURV[*]}"
[ $stale -eq 0 ] && [ $unviable -eq 0 ] && [ $survived -eq 0 ]
