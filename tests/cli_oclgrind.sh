#!/bin/bash
# Every mode under Oclgrind, the OpenCL simulator that checks every memory
# access, API call and (--data-races) unsynchronised access: tiny renders run
# clean (nothing in Oclgrind's log) and give PoCL's image within the tolerance
# between two compilers. A kernel with an out-of-range read must be caught,
# or a clean log would prove nothing. Oclgrind is not an ICD in Debian: the
# `oclgrind` wrapper preloads it and it is then the only platform; registered
# as one beside PoCL, it is numbered last and left out of --device all.
# (--uninitialized is not used: it aborts on LLVM's freeze instruction.)
source "$(dirname "$0")/lib_cli.sh"
source "$HERE/lib_platforms.sh"
OG=(oclgrind --check-api --data-races)

# grind NAME LOG ARGS...: specmip render ARGS under Oclgrind, its messages in LOG.
grind() {
    local name=$1 log=$2; shift 2
    rm -f "$log"
    "${OG[@]}" --log "$log" "$BIN" render "$@" > "$T/og.out" 2> "$T/og.err"
    local rc=$?
    check "$name: exit 0 under Oclgrind (got $rc)" test $rc -eq 0
    [ $rc -eq 0 ] || cat "$T/og.err" >&2
}

check "the simulator is the device" \
    test "$("${OG[@]}" "$BIN" devices | grep -c '^  device 0: Oclgrind Simulator')" = 1

R=(--width 24 --height 18 --spp 2 --seed 9 --quiet)
# and the environment map's trace kernel (its lookup and sampling, with the
# conductor, the coated type and smooth shading beside it)
RUNS+=("rgb $DATA/scenes/envmap.scene")
# and the kinds of light that are not triangles: point, spot, distant, the
# sky (an environment map) and its sun
RUNS+=("ml $DATA/tests/data/scenes/delta_lights.scene")
# and textured paths: an image on a reflectance (the trilinear pick, the
# lift of its texel, the roulette's survival from it) and one on an area
# light's emission (the tap at the hit and at the light sample)
RUNS+=("ml $DATA/scenes/textured.scene" "truth $DATA/scenes/emissive_texture.scene")
for run in "${RUNS[@]}"; do
    set -- $run
    mode=$1; shift
    name="$mode $(basename "$1" .scene)${2:+ $2 $3}"
    grind "$name" "$T/og.log" "$@" --mode "$mode" "${R[@]}" -o "$T/o.exr"
    if [ -s "$T/og.log" ]; then
        bad "$name: Oclgrind reported errors"
        head -40 "$T/og.log" >&2
    else
        ok
    fi
    "$BIN" render "$@" --mode "$mode" "${R[@]}" -o "$T/p.exr"
    check "$name: PoCL render exit 0" test $? -eq 0
    close_images "$name: Oclgrind vs PoCL" "$T/p.exr" "$T/o.exr"
done

# The light tree's walk (kernels/light_tree.clh) on a street of 128 lamps
# (tools/lamp_street.sh), mixed power, walls that face both ways: Oclgrind's
# log clean, and PoCL's two compilers (pthread, basic) and Oclgrind each as
# the CPU reference (host/cpu/refcpu_light_tree.c) within the tolerance
# between compilers. Every choice of the walk is a continuous function of
# the shading point, so the float differences between them flip as few
# paths as elsewhere (a fallback that switched at a threshold differed by
# a mean dE00 of 0.17 on such a street).
"$ROOT/tools/lamp_street.sh" 16 4 > "$T/street.scene"
S=("$T/street.scene" --mode rgb --light-sampler tree --width 32 --height 18 --spp 2 --seed 9 --quiet)
grind "light tree" "$T/og.log" "${S[@]}" -o "$T/tree-og.exr"
check "light tree: Oclgrind's log is empty" test ! -s "$T/og.log"
"$BIN" render "${S[@]}" --backend cpu -o "$T/tree-cpu.exr"
check "light tree: CPU reference exit 0" test $? -eq 0
for dev in pthread basic; do
    POCL_DEVICES=$dev "$BIN" render "${S[@]}" -o "$T/tree-$dev.exr"
    check "light tree: PoCL $dev exit 0" test $? -eq 0
    close_images "light tree: PoCL $dev vs the CPU reference" "$T/tree-$dev.exr" "$T/tree-cpu.exr"
done
close_images "light tree: Oclgrind vs the CPU reference" "$T/tree-og.exr" "$T/tree-cpu.exr"

# The light integrator's program (kernels/lighttrace.cl; hero: the shade
# kernel's work-group set-up and the chunk's key offset), clean and as PoCL's.
grind "light hero" "$T/og.log" "$DATA/scenes/cornell_spiky.scene" --integrator light --mode hero \
    "${R[@]}" -o "$T/o.exr"
check "light hero: Oclgrind's log is empty" test ! -s "$T/og.log"
"$BIN" render "$DATA/scenes/cornell_spiky.scene" --integrator light --mode hero "${R[@]}" -o "$T/p.exr"
close_images "light hero: Oclgrind vs PoCL" "$T/p.exr" "$T/o.exr"
# Its dispersive splats (a subpath committed to a wavelength at the prism,
# kernels/shade.cl disp_splats) on the prism wall, and its light-flow walk of
# fluorescent subpaths (kernels/shade_splats.clh) on the two-dye relay.
for run in "prism $DATA/scenes/prism_wall.scene --width 32 --height 8 --spp 4" \
    "relay $DATA/tests/data/scenes/fluor_relay.scene --width 16 --height 16 --spp 2"; do
    set -- $run
    name="light $1"
    shift
    grind "$name" "$T/og.log" "$@" --integrator light --mode ml --seed 9 --quiet -o "$T/o.exr"
    check "$name: Oclgrind's log is empty" test ! -s "$T/og.log"
    "$BIN" render "$@" --integrator light --mode ml --seed 9 --quiet -o "$T/p.exr"
    check "$name: not black" awk -v a="$(iinfo --stats "$T/p.exr" | sed -n 's/^ *Stats Max: *//p' | awk '{print $1 + $2 + $3}')" 'BEGIN { exit !(a > 0) }'
    close_images "$name: Oclgrind vs PoCL" "$T/p.exr" "$T/o.exr"
done

# The bidirectional integrator's program (kernels/bdpt.cl: both subpaths,
# every strategy's record in the next slot, the records' exponent and sums).
BD=("$DATA/scenes/cornell.scene" --integrator bdpt --mode ml --width 8 --height 8 --spp 1 --seed 9 --quiet)
grind "bdpt" "$T/og.log" "${BD[@]}" -o "$T/o.exr"
check "bdpt: Oclgrind's log is empty" test ! -s "$T/og.log"
"$BIN" render "${BD[@]}" -o "$T/p.exr"
close_images "bdpt: Oclgrind vs PoCL" "$T/p.exr" "$T/o.exr"

# Registered as an ICD beside PoCL (Debian does not register it), the
# simulator claims every device type, so the loader lists it first; specmip
# numbers it after PoCL's CPU device and --device all leaves it out.
V=$T/vendors
mkdir "$V"
cp /etc/OpenCL/vendors/pocl.icd "$V/"
echo "$(dpkg -L oclgrind | grep -m1 '/liboclgrind-rt-icd\.so$')" > "$V/oclgrind.icd"
first=$(OCL_ICD_VENDORS=$V clinfo -l | sed -n 's/^Platform #0: //p')
check "registered: the loader lists Oclgrind first (got '$first'; else this proves nothing)" \
    test "$first" = Oclgrind
OCL_ICD_VENDORS=$V "$BIN" devices > "$T/devices.txt"
check "registered: devices exits 0" test $? -eq 0
check "registered: PoCL is platform 0" grep -q '^platform 0: Portable Computing Language' "$T/devices.txt"
check "registered: the simulator is device 1" grep -q '^  device 1: Oclgrind Simulator' "$T/devices.txt"
check "registered: devices says the simulator is not in all" \
    grep -q 'not in --device all (a simulator)' "$T/devices.txt"
OCL_ICD_VENDORS=$V "$BIN" render "${R[@]}" --device all --json -o "$T/all.exr" > "$T/all.json"
check "registered: --device all takes PoCL alone" \
    jq -e '[.devices[].name] | length == 1 and (.[0] | test("Oclgrind") | not)' "$T/all.json" > /dev/null
check "under the wrapper: --device all takes the simulator" \
    test "$("${OG[@]}" "$BIN" render "${R[@]}" --device all --json -o "$T/all.exr" | jq -r '.devices[0].name')" \
    = "0: Oclgrind Simulator"

# The same check on kernels with one read past the end of a buffer.
B=$T/broken
mkdir "$B"
cp -r "$DATA/include" "$DATA/kernels" "$B/"
ln -s "$DATA/scenes" "$B/scenes"
ln -s "$DATA/spectra" "$B/spectra"
sed -i 's/^    out\[2\] = sz;/    out[2] = sz + xyz[SPM_PATH_CH * (size_t)npix * spp];/' "$B/kernels/shade.cl"
check "broken kernel made" grep -q 'sz + xyz\[SPM_PATH_CH \* (size_t)npix \* spp\]' "$B/kernels/shade.cl"
SPECMIP_DATA=$B grind "read past the end" "$T/bad.log" --mode rgb "${R[@]}" -o "$T/b.exr"
check "read past the end: Oclgrind reports it" grep -q 'Invalid read' "$T/bad.log"
finish
