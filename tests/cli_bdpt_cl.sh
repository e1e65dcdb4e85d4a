#!/bin/bash
# specmip render --integrator bdpt on the OpenCL backend (kernels/bdpt.cl):
# the same camera and light subpaths as the CPU reference (the same RNG
# dimensions per vertex), the same strategies and MIS weights, image by image
# within a measured float tolerance: a levelled mode on a diffuse box, a
# conductor's factors, glass (delta vertices, a medium's absorption), a point
# light seen through a thin lens, a spectral EXR, spot, distant and two-sided
# lights; one device and two (PoCL's
# "pthread basic") giving the same pixels bit for bit (the records' values
# summed in fixed point do not depend on the order of the adds nor on which
# device renders a pass); the reference's refusals on the device. That the
# estimator converges to the path and light tracers is test_bdpt_converge's
# (on the reference), its weights' sum test_bdpt_mis's; here the device's
# image mean is checked against the device's own path tracer too.
source "$(dirname "$0")/lib_cli.sh"
avg() { iinfo --stats "$1" | sed -n 's/^ *Stats Avg: *//p' | awk '{print $1 + $2 + $3}'; }

# Kernel against reference. Measured (AMD EPYC, PoCL 5, seed 5): the largest
# channel's mean relative difference below 1e-6 on the diffuse, metal and
# lens scenes, no pixel channel beyond 1e-3; 1.4e-4 on glass (0.17 % of
# channels beyond 1e-3: a few paths through glass take another branch after
# a transcendental rounded differently, as kernels/trace.cl's head says). The
# bounds are 1e-4 (1e-3 through glass) and 1 %: a wrong MIS weight or a
# dropped factor moves whole strategies.
same_as_reference() { # NAME SCENE SPP BOUND OUT-SUFFIX ARGS...
    local name=$1 scene=$2 spp=$3 bound=$4 ext=$5
    shift 5
    local a=(render "$scene" --integrator bdpt --width 24 --height 24 --spp "$spp" --seed 5 --quiet "$@")
    "$BIN" "${a[@]}" -o "$T/$name-cl.$ext" 2> "$T/$name.err"
    check "$name, OpenCL: exit 0" test $? -eq 0
    "$BIN" "${a[@]}" --backend cpu -o "$T/$name-cpu.$ext"
    check "$name, reference: exit 0" test $? -eq 0
    check "$name: not black" below 1e-3 "$(avg "$T/$name-cl.$ext")"
    local m b
    m=$(relavg "$T/$name-cl.$ext" "$T/$name-cpu.$ext")
    b=$(beyond "$T/$name-cl.$ext" "$T/$name-cpu.$ext")
    check "$name: mean relative difference $m below $bound" below "$m" "$bound"
    check "$name: share beyond 1e-3 relative $b below 1 %" below "$b" 0.01
}
# a levelled mode, every spectral bin of the EXR too
same_as_reference ml "$DATA/scenes/cornell_spiky.scene" 16 1e-4 spectral.exr --mode ml
same_as_reference metals "$DATA/scenes/metals.scene" 8 1e-4 exr --mode ml
# smooth glass (the scene's rough block made smooth: delta vertices alone)
sed 's/^material rough .*/material rough     dielectric ior 1.5/' "$DATA/scenes/glass.scene" \
    > "$T/glass.scene"
cp "$DATA/scenes/materials_sphere.ply" "$T/"
check "the glass scene has no rough glass" test "$(grep -c '^material.*alpha' "$T/glass.scene")" = 0
same_as_reference glass "$T/glass.scene" 8 1e-3 exr --mode ref
# rough glass, absorbing (a join's length inside the slab): the refraction's
# eval in both modes, its reverse densities, the length of a join inside the
# slab and of a joined light vertex's arriving segment. Measured (seed 5,
# 24 x 24, 8 spp; other seeds, 32 x 32 and mode ml alike): mean relative difference
# 1.9e-7, no channel beyond 1e-3. One side's error shows: the kernel's
# radiance-mode refraction without its 1 / e^2 gives 1.9e-3 (10 % of channels
# beyond), its join inside the slab without its length 4.9e-4 (8.5 %).
sed 's/^material frosted .*/material frosted   dielectric ior 1.5 alpha 0.3 absorb green 8/' \
    "$DATA/scenes/frosted_lamp.scene" > "$T/frosted.scene"
check "the frosted slab absorbs" grep -q "alpha 0.3 absorb" "$T/frosted.scene"
same_as_reference frosted "$T/frosted.scene" 8 1e-4 exr --mode ref
# a thin lens (its lens point from the vertex's own dimensions) and a point light
sed 's/^camera position \(.*\) fov 40$/camera position \1 fov 40 aperture 0.05 focus 1.0/' \
    "$DATA/scenes/cornell.scene" > "$T/lens.scene"
echo "light point 0.3 0.4 0.3 equal 5" >> "$T/lens.scene"
check "the lens scene has its lens" grep -q "aperture 0.05" "$T/lens.scene"
same_as_reference lens "$T/lens.scene" 8 1e-4 exr --mode ml
# dispersive glass and hero wavelengths in one program (a kernel build is
# the cost here): a prism throws an area light's spectrum onto a wall (a
# sample's bin committed by whichever subpath meets the glass first, carried
# by the connected path's first dispersive vertex, shaded in one lane); the
# wall's other paths shaded at their sample's hero set (each record's lanes
# from its sample's key, the record slots' order being the atomic counter's)
sed 's/^light spot .*/material lamp emit equal 600\nquad lamp -3.211547 -0.3 1.688169  -3.211547 0.3 1.688169  -3.157737 0.3 2.285751  -3.157737 -0.3 2.285751/' \
    "$DATA/scenes/prism_wall.scene" > "$T/prism_area.scene"
check "the prism's light is an area light" grep -q "^quad lamp" "$T/prism_area.scene"
same_as_reference prism_hero "$T/prism_area.scene" 8 1e-4 exr --mode hero
# the light kinds beyond area and point lights in one program: the ceiling
# gone, a distant light through the opening (a light at infinity: its
# subpaths leave the bounding sphere's disc, camera vertices joined along its
# direction), a spot and a two-sided panel (its emission leaving either face,
# its back seen by the camera)
sed -e '/^quad white  0.556 0.549 0.559  0.000/d' \
    -e 's/^material light .*/material light emit equal 300 twosided/' \
    -e 's/^quad light .*/quad light  0.343 0.40 0.332  0.213 0.40 0.332  0.213 0.40 0.227  0.343 0.40 0.227\nlight distant 0.2 -1 0.3 equal 2\nlight spot 0.45 0.5 0.2 0.4 0 0.3 equal 5 cone 40/' \
    "$DATA/scenes/cornell.scene" > "$T/lights.scene"
check "the lights scene has its three kinds" test "$(grep -c '^light \|twosided' "$T/lights.scene")" = 3
same_as_reference lights "$T/lights.scene" 8 1e-4 exr --mode ml

# The device's BDPT against its own path tracer: the image means within 3 %
# (measured 0.65 % apart at 128 and 512 spp, seed 7; two BDPT renders at 8
# spp 3.8 % apart, so about 1 % of noise at 128).
L=(render "$T/lens.scene" --mode ml --width 24 --height 24 --seed 7 --quiet)
"$BIN" "${L[@]}" --integrator bdpt --spp 128 -o "$T/lb.exr"
"$BIN" "${L[@]}" --spp 512 -o "$T/lp.exr"
check "bdpt and path tracing, OpenCL: the same mean within 3 %" \
    below "$(awk -v a="$(avg "$T/lb.exr")" -v b="$(avg "$T/lp.exr")" 'BEGIN { d = a / b - 1; print d < 0 ? -d : d }')" 0.03

# Split invariance: one device against two, 64 x 64 at 32 spp (two passes of
# 16, which the devices share; SPECMIP_TEST_MEET: they meet at their first).
S=(render "$DATA/scenes/cornell_spiky.scene" --integrator bdpt --mode ml --width 64 --height 64 --spp 32 --seed 3 --quiet)
split_invariant "${S[@]}"

# The reference's refusals hold on the device, with their reasons.
no_bdpt() { # no_bdpt NAME PATTERN ARGS...: exit 2, PATTERN on stderr, no output
    local what=$1 why=$2
    shift 2
    rm -f "$T/no.exr"
    "$BIN" render "$@" --integrator bdpt --width 8 --height 8 --spp 1 -o "$T/no.exr" 2> "$T/no.err"
    check "$what, OpenCL: exit 2" test $? -eq 2
    check "$what, OpenCL: says why ($why)" grep -q "$why" "$T/no.err"
    check "$what, OpenCL: nothing written" test ! -e "$T/no.exr"
}
no_bdpt "coated" "'coated' picks one of its terms" "$DATA/scenes/coated.scene"
finish
