# The kernels compile without a single warning for an x86-64 CPU without
# AVX-512: PoCL prints the compiler's "N warnings generated." on the terminal
# of whoever builds them first. Compiled with the clang PoCL itself uses
# (Debian's libpocl2 depends on clang-15), for x86-64-v3 (AVX2, no AVX-512).
# What is compiled is every program the host builds, as it builds it: the
# list comes from the host's own lists (tests/kernel_variants.c: the render's
# program in every mode with every slot, without and with each spectral
# output, at the vector counts of every bundled scene; the ray replay's two
# builds, kernels/rays.cl; the operator benchmark's), each program's files
# joined into one source as clCreateProgramWithSource joins them.
source "$(dirname "$0")/lib_cli.sh"
CLANG=$(command -v clang-15 || command -v clang) || { echo "FAIL: no clang-15" >&2; exit 1; }
VARIANTS=${KERNEL_VARIANTS:-$PWD/kernel_variants}
[ -x "$VARIANTS" ] || { echo "FAIL: no kernel_variants at $VARIANTS (built with the tests)" >&2; exit 1; }
compile() {  # compile OPT "FILES" OPTIONS...: 0 when clang accepts the program with no diagnostic at all
    local opt=$1 files=$2 f; shift 2
    : > "$T/prog.cl"
    for f in $files; do cat "$ROOT/$f" >> "$T/prog.cl" || return 1; done
    # shellcheck disable=SC2068
    "$CLANG" -x cl -cl-std=CL1.2 -Xclang -finclude-default-header -target x86_64-unknown-linux-gnu \
        -march=x86-64-v3 "$opt" -S -emit-llvm -o /dev/null -I "$ROOT/include" -I "$ROOT/kernels" \
        -DSPM_BVH_STACK=64 $@ "$T/prog.cl" 2>"$T/log"
    local rc=$?
    if [ $rc -ne 0 ] || [ -s "$T/log" ]; then
        echo "--- $files $*:" >&2
        head -20 "$T/log" >&2
        return 1
    fi
}
# the bundled scenes, a conductor scene (its type's kernel code) and one with
# smooth meshes (the shading frame's: tools/gen_meshes.py smooth_box.scene)
python3 "$ROOT/tools/gen_meshes.py" "$T/gen" > /dev/null || bad "gen_meshes.py"
# and the light kinds of the `light` statement (their kernel files)
printf 'image 8 8\ncamera position 0 2 -2 direction 0 -1 1 fov 40\nspectrum e equal\nmaterial w reflect e 0.5\nquad w -1 0 -1  -1 0 1  1 0 1  1 0 -1\n%s\n' \
    'light point 0 1 0 e 3' > "$T/lights.scene"
"$VARIANTS" "$DATA"/scenes/*.scene "$DATA"/tests/data/scenes/conductor_box.scene \
    "$T/gen/smooth_box.scene" "$T/lights.scene" > "$T/variants" 2> "$T/variants.err"
rc=$?
check "kernel_variants lists the programs (exit $rc: $(head -1 "$T/variants.err"))" test $rc -eq 0
sort -u "$T/variants" > "$T/programs"
# what the list must hold, so that an empty or partial one cannot pass
check "the list has the render's program" grep -q "^kernels/trace.cl kernels/shade.cl	" "$T/programs"
check "the list has the light integrator's program" grep -q "^kernels/trace.cl kernels/shade.cl kernels/lighttrace.cl	.*-DSPM_LIGHT_TRACE" "$T/programs"
check "the list has spectral output builds" grep -q "	.*-DSPM_SPEC_BINS=" "$T/programs"
check "the list has conductor builds" grep -q "	.*-DSPM_WITH_CONDUCTOR" "$T/programs"
check "the list has dielectric builds" grep -q "	.*-DSPM_WITH_DIELECTRIC" "$T/programs"
check "the list has smooth-shading builds" grep -q "	.*-DSPM_WITH_SMOOTH" "$T/programs"
check "the list has point-light builds" grep -q "	.*-DSPM_WITH_LIGHT_POINT" "$T/programs"
check "the list has the ray replay's builds (one ray, packets, quantised; timed and counting)" test "$(grep -c "^kernels/rays.cl	" "$T/programs")" -eq 6
check "the list has a program for every mode's kernel" test "$(grep -c "^kernels/trace.cl" "$T/programs")" -ge \
    "$("$BIN" modes | wc -l)"
if [ -n "${KERNEL_WARNINGS_LIST_ONLY:-}" ]; then
    # the sanitizer build (tests/CMakeLists.txt): clang's diagnostics are the
    # same in every build, so the normal build's run compiles; here the list's
    # host code runs under the sanitizers
    echo "listed $(wc -l < "$T/programs") programs; compiled in the normal build's run" >&2
    finish
    exit
fi
# Every program through clang's front end and IR generation (-O0), where its
# diagnostics come from. The optimizer's own warnings (-O2) are only for loop
# hints it could not honour (-Wpass-failed), and the kernels hold none: so
# -O2, four times the cost, compiles the largest program of each file set (the
# one with the most options), unless a loop hint appears, then every program.
if grep -rqE '#[[:space:]]*pragma[[:space:]]+(unroll|nounroll|clang[[:space:]]+loop)|opencl_unroll_hint' \
        "$ROOT/kernels" "$ROOT/include"; then
    every_o2=1 level=-O2
else
    every_o2= level=-O0
fi
n=0
while IFS=$'\t' read -r files opts; do
    n=$((n + 1))
    # shellcheck disable=SC2086
    check "$files $opts" compile $level "$files" $opts
done < "$T/programs"
# the largest program of each file set: most options, then the longest line
awk -F'\t' '{ o = $2; print gsub(/-D/, "", o) "\t" length($0) "\t" $0 }' "$T/programs" |
    sort -t$'\t' -k3,3 -k1,1nr -k2,2nr | awk -F'\t' '!seen[$3]++ { print $3 "\t" $4 }' > "$T/largest"
check "one largest program for each file set" test "$(wc -l < "$T/largest")" -eq "$(cut -f1 "$T/programs" | sort -u | wc -l)"
[ -n "$every_o2" ] || while IFS=$'\t' read -r files opts; do
    # shellcheck disable=SC2086
    check "-O2: $files $opts" compile -O2 "$files" $opts
done < "$T/largest"
echo "compiled $n programs, $(wc -l < "$T/largest") of them also at -O2${every_o2:+ (all: loop hints)}" >&2
finish
