# The kernels compile without a single warning for an x86-64 CPU without
# AVX-512: PoCL prints the compiler's "N warnings generated." on the terminal
# of whoever builds them first. Compiled with the clang PoCL itself uses
# (Debian's libpocl2 depends on clang-15), for x86-64-v3 (AVX2, no AVX-512),
# with every shade kernel and the vector counts ml and mlc give them.
source "$(dirname "$0")/lib_cli.sh"
CLANG=$(command -v clang-15 || command -v clang) || { echo "FAIL: no clang-15" >&2; exit 1; }
compile() {  # compile FILE DEFINES...: 0 when clang accepts it with no diagnostic at all
    local file=$1; shift
    "$CLANG" -x cl -cl-std=CL1.2 -Xclang -finclude-default-header -target x86_64-unknown-linux-gnu \
        -march=x86-64-v3 -O2 -S -emit-llvm -o /dev/null -I "$ROOT/include" -I "$ROOT/kernels" \
        -DSPM_BVH_STACK=64 -DSPM_DEVICE_INDEX=0 "$@" "$ROOT/kernels/$file" 2>"$T/log"
    local rc=$?
    if [ $rc -ne 0 ] || [ -s "$T/log" ]; then
        echo "--- $file $*:" >&2
        head -20 "$T/log" >&2
        return 1
    fi
}
all_shade="-DSPM_SHADE_RGB -DSPM_SHADE_HERO"
check "trace.cl" compile trace.cl
check "trace.cl, every type" compile trace.cl -DSPM_WITH_LAMBERT -DSPM_WITH_AREA
# shellcheck disable=SC2086
check "shade.cl, ml widths" compile shade.cl -DSPM_SHADE_L0_NV=25 -DSPM_SHADE_L1_NV=5 \
    -DSPM_SHADE_L2_NV=5 -DSPM_SHADE_L3_NV=5 -DSPM_SHADE_L4_NV=5 $all_shade
check "shade.cl, mlc widths" compile shade.cl -DSPM_SHADE_L0_NV=26 -DSPM_SHADE_L1_NV=6 \
    -DSPM_SHADE_L2_NV=7 -DSPM_SHADE_L3_NV=9 -DSPM_SHADE_L4_NV=13
check "opbench.cl" compile opbench.cl
finish
