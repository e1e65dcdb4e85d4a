#!/bin/bash
# Fluorescence along light subpaths (--integrator light, docs/METHODS.md
# "Fluorescence", "Light subpaths"): the light's spectrum carried from the
# lamp, each fluorescent vertex's matrix M = diag(D) + F applied to what
# arrives (light-flow order); and in the bidirectional integrator
# (--integrator bdpt, docs/BDPT.md "Fluorescence in light-flow order on both
# subpaths"), each connected path, whichever strategy made it, shaded once
# from its light end.
#  - closed form: a dye wall (absorption 0.5, yield 0.8, SPEC 1, emission
#    flat over 600-640 nm) under a point light of a 449-451 nm line, as
#    cli_fluor.sh's wall under a line background: every splat is M applied to
#    the line, so flat / line integral = 0.8 x 0.5 / (41 x 0.5) = 0.8 / 41 in
#    every mode with spectra, on both backends (a skipped or transposed
#    re-radiation leaves the 600-640 nm bins dark: 0); bdpt's connected paths
#    (the light joined to a camera vertex, a light vertex seen by the camera)
#    are M applied to the line too;
#  - kernel against reference: the same subpaths (the same RNG streams) give
#    the same image within the float tolerance cli_light_cl.sh measured, on
#    fluor_relay.scene (two dyes in series) and scenes/fluorescent.scene; bdpt
#    (cli_bdpt_cl.sh's bound) on the relay with an area light (camera
#    vertices that hit the lamp, s = 0, carry its emission on a fluorescent
#    vertex), on scenes/fluorescent.scene and on a Donaldson matrix;
#  - a conductor on a fluorescent subpath: walls that fluoresce with
#    absorption 0 give the image of plain walls (the conductor's Fresnel
#    factor at the camera connection's cosine and at the sampled ray's);
#  - hero mode refuses a fluorescent scene in both integrators, saying why.
# That light and path tracing converge on fluorescent scenes is
# test_light_integrator's (per pixel, against measured noise); bdpt against
# both, test_bdpt_converge's.
source "$(dirname "$0")/lib_cli.sh"
PY=${SPECMIP_PYTHON:-$(cd "$(dirname "$BIN")" && pwd)/pyenv/bin/python}
"$PY" -c "import OpenImageIO, numpy" 2> /dev/null || skip "no OpenImageIO/numpy for $PY"

cat > "$T/wall.scene" << 'SCENE'
image 12 8
camera position 0 0 -1  direction 0 0 1  fov 40
spectrum white   equal
spectrum abs     inline 380 0.5 780 0.5 end
spectrum flat    inline 380 0 599 0 600 1 640 1 641 0 780 0 end
spectrum line    inline 380 0 449 0 450 1 451 0 780 0 end
material dye reflect white fluoresce abs flat 0.8
light point 0 0 -0.5 line 1
quad dye  -10 -10 0  10 -10 0  10 10 0  -10 10 0
SCENE
# ratio FILE: the flat emission's mean per nm over the reflected line's integral
ratio() { "$PY" "$HERE/spectral_stats.py" "$1" | awk '{print $3}'; }
for run in "light cpu truth" "light cpu ref" "light cpu ml" "light cpu mlc" "light opencl ml" \
    "light opencl mlc" "bdpt cpu truth" "bdpt cpu ml" "bdpt opencl ml" "bdpt opencl mlc"; do
    read -r i be m <<< "$run"
    w="$T/w-$i-$m-$be.spectral.exr"
    "$BIN" render "$T/wall.scene" --integrator "$i" --mode "$m" --backend "$be" --spp 4 --quiet \
        -o "$w" 2> "$T/err"
    check "wall $i $m $be: render ($(tail -1 "$T/err"))" test -s "$w"
    r=$(ratio "$w")
    echo "wall $i $m $be: flat emission / reflected line = $r (closed form 0.8/41 = 0.0195122)"
    # float sums over a few hundred bins: relative rounding ~1e-6 (measured
    # 0.0195121902 to 0.0195121946)
    check "wall $i $m $be: the closed form" near "$r" 0.0195122 2e-6
done

avg() { iinfo --stats "$1" | sed -n 's/^ *Stats Avg: *//p' | awk '{print ($1 < 0 ? -$1 : $1) + ($2 < 0 ? -$2 : $2) + ($3 < 0 ? -$3 : $3)}'; }
# Kernel against reference: the largest channel's mean relative difference
# (lib_cli.sh relavg; cli_light_cl.sh's bound).
# bdpt's measured 0 on all three at 24 x 24, 8 spp, seed 5; 2.5e-3 on the
# relay when the device dropped the emission a fluorescent camera vertex's
# ray hit.
RELAY=$DATA/tests/data/scenes/fluor_relay.scene
sed 's/^light spot .*/material lamp emit band 40\nquad lamp -0.3 1 1.2  0.3 1 1.2  0.3 1 1.8  -0.3 1 1.8/' \
    "$RELAY" > "$T/relay_area.scene"
check "the relay's light is an area light" grep -q "^quad lamp" "$T/relay_area.scene"
for run in "light $RELAY ml" "light $RELAY rgb" "light $DATA/scenes/fluorescent.scene mlc" \
    "bdpt $T/relay_area.scene ml" "bdpt $DATA/scenes/fluorescent.scene mlc" \
    "bdpt $DATA/scenes/donaldson.scene ref"; do
    read -r i scene m <<< "$run"
    name="$i-$(basename "$scene" .scene)-$m"
    a=(render "$scene" --integrator "$i" --mode "$m" --width 24 --height 24 --spp 8 --seed 5 --quiet)
    "$BIN" "${a[@]}" -o "$T/$name-cl.exr" 2> "$T/err"
    check "$name, OpenCL: exit 0 ($(tail -1 "$T/err"))" test -s "$T/$name-cl.exr"
    "$BIN" "${a[@]}" --backend cpu -o "$T/$name-cpu.exr"
    check "$name, reference: exit 0" test -s "$T/$name-cpu.exr"
    check "$name: not black" num "$(avg "$T/$name-cl.exr")" '>' 1e-3
    d=$(relavg "$T/$name-cl.exr" "$T/$name-cpu.exr")
    echo "$name: kernel against reference, mean relative difference $d"
    check "$name: kernel as the reference (mean relative difference $d below 1e-4)" num "$d" '<' 1e-4
done

# A conductor on a fluorescent subpath (measured mean dE00 ~1e-6, rounding).
FC="$DATA/tests/data/scenes/fluor_conductor.scene"
sed 's/^material wall .*/material wall reflect white/' "$FC" > "$T/fc_plain.scene"
for be in opencl cpu; do
    "$BIN" render "$FC" --integrator light --backend "$be" --mode ml --spp 8 --quiet -o "$T/fc.exr"
    check "fluorescent + conductor $be renders" test $? -eq 0
    "$BIN" render "$T/fc_plain.scene" --integrator light --backend "$be" --mode ml --spp 8 --quiet \
        -o "$T/fc_plain.exr"
    check "plain + conductor $be renders" test $? -eq 0
    "$BIN" compare "$T/fc.exr" "$T/fc_plain.exr" --json > "$T/fc.json"
    echo "fluorescent + conductor $be: mean dE00 against plain walls $(jnum "$T/fc.json" .mean)"
    check "fluorescent + conductor $be: the conductor shaded alike (mean dE00 $(jnum "$T/fc.json" .mean))" \
        num "$(jnum "$T/fc.json" .mean)" '<' 1e-3
done

for run in "hero light opencl:hero mode cannot render fluorescent" \
    "hero bdpt cpu:hero mode cannot render fluorescent"; do
    read -r m i be <<< "${run%%:*}"
    "$BIN" render "$T/wall.scene" --integrator "$i" --mode "$m" --backend "$be" --quiet \
        -o "$T/no.exr" 2> "$T/err"
    rc=$?
    check "$m --integrator $i refuses a fluorescent scene with exit 2 (got $rc)" test $rc -eq 2
    check "$m --integrator $i says why: $(cat "$T/err")" grep -q "${run#*:}" "$T/err"
    check "$m --integrator $i writes no image" test ! -e "$T/no.exr"
done
finish
