# Shared by the tests that run the kernels on other OpenCL implementations
# than PoCL (Mesa's Rusticl, Oclgrind) and compare their images with PoCL's.
# Sourced after lib_cli.sh.

# Rusticl keeps its compiled kernels in Mesa's shader cache, as PoCL does in
# POCL_CACHE_DIR: beside the build, not in the user's home.
export MESA_SHADER_CACHE_DIR=${MESA_SHADER_CACHE_DIR:-$(cd "$(dirname "$BIN")" && pwd)/mesa-cache}

# The scenes and options that make every mode build every kernel it has:
# truth (level 0 alone: 25 x float16), ref (level 1 alone), hero, rgb; ml
# at levels 2 and 3 (float8, float4) and at 1 to 4 (float16, float8, float4,
# float2: saturated_box); mlc at levels 2, 3 and 4 with the spike lanes of
# cornell_spiky. ml's level 0 is truth's kernel; a program holding it builds
# for about 100 s on Rusticl, so it is built once, for truth.
SPIKY=$DATA/scenes/cornell_spiky.scene
RUNS=("truth $SPIKY" "ref $SPIKY" "hero $SPIKY" "rgb $SPIKY" "ml $SPIKY"
      "ml $DATA/scenes/saturated_box.scene --coarsest-level 4"
      "mlc $SPIKY --coarsest-level 4")

# platform_device NAME: the index of the first device of the platform whose
# name begins with NAME, as `specmip devices` numbers it (empty if none).
platform_device() {
    "$BIN" devices | awk -v p="$1" '
        /^platform / { name = $0; sub(/^platform [0-9]+: /, "", name); on = index(name, p) == 1 }
        on && /^  device / { sub(/:$/, "", $2); print $2; exit }'
}

# The tolerance between two OpenCL compilers on the same kernels. Both build
# without fast math, with correctly rounded divide/sqrt and contraction as the
# source asks; what differs is how each evaluates sin/cos/exp/pow (a few ulps
# allowed). That changes a path's value by ~1e-6 relative (dE00 ~1e-5), and
# flips a discrete decision (a ray within ulps of a triangle edge) for at
# most 1 path in 1000 (test_multidevice_mixed). compare blurs 5x5, so with
# at most 4 spp per pixel from the other compiler, as here, those flips touch
# at most 1e-3 x 4 x 25 = 10% of the pixels: the median pixel is unflipped and within 1e-3, while an image only
# 0.05% too dark has a median of 3.5e-3 (measured on cornell_spiky). One
# flipped path changes 25 blurred pixels by 1/(25 spp) of their value, 2% at
# 2 spp, ~0.14 dE00 (1% darker measures 0.07): on the >= 432 pixels of these
# images the mean moves by ~0.01, so even a path ten times its pixel's value
# stays below 0.1, the bound cli_multidevice applies to PoCL's two compilers.
KERNEL_TOL_MEDIAN=1e-3
KERNEL_TOL_MEAN=0.1

# close_images WHAT A B: dE00 between A and B within those bounds and no
# non-finite pixel (the measured values go to the log).
close_images() {
    local what=$1 a=$2 b=$3
    if ! "$BIN" compare "$a" "$b" --json > "$T/cmp.json"; then
        bad "$what: compare failed"
        return
    fi
    echo "$what: dE00 median $(jq .median "$T/cmp.json"), mean $(jq .mean "$T/cmp.json"), max $(jq .max "$T/cmp.json")"
    check "$what: dE00 median <= $KERNEL_TOL_MEDIAN, mean <= $KERNEL_TOL_MEAN, all finite" \
        jq -e --argjson md "$KERNEL_TOL_MEDIAN" --argjson mn "$KERNEL_TOL_MEAN" \
        '.nonfinite == 0 and .median <= $md and .mean <= $mn' "$T/cmp.json" > /dev/null
}
