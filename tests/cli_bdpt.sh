#!/bin/bash
# specmip render --integrator bdpt (the CPU reference): a render of the Cornell
# box that records its integrator and gives the same pixels again, and not the
# light tracer's; what it refuses, each with its reason, exit 2 and nothing
# written: a type whose vertex picks its term (coated). Dispersive glass:
# the prism seen through, against the path tracer; hero wavelengths against
# truth. The OpenCL kernel against this reference is
# tests/cli_bdpt_cl.sh. How it converges to the path and light
# tracers is tests/test_bdpt_converge.c, its MIS weights tests/test_bdpt_mis.c.
source "$(dirname "$0")/lib_cli.sh"
CORNELL=$DATA/scenes/cornell.scene
B=(render "$CORNELL" --backend cpu --integrator bdpt --width 32 --height 32 --seed 5 --spp 8 --quiet)

"$BIN" "${B[@]}" -o "$T/a.exr" 2> "$T/a.err"
check "bdpt: exit 0" test $? -eq 0
check "bdpt: records its integrator" \
    sh -c "oiiotool --info -v '$T/a.exr' | grep -q 'specmip:integrator: \"bdpt\"'"
"$BIN" "${B[@]}" -o "$T/b.exr" 2> "$T/b.err"
check "bdpt: the same pixels again" same_pixels "$T/a.exr" "$T/b.exr"
"$BIN" render "$CORNELL" --backend cpu --integrator light --width 32 --height 32 --seed 5 \
    --spp 8 --quiet -o "$T/l.exr"
check "bdpt and light: other pixels" other_pixels "$T/a.exr" "$T/l.exr"

# Dispersive glass, the camera's side: the camera sees a slit only through a
# prism, so the one strategy that makes these paths is s = 0 (no join meets a
# delta vertex), weighed 1, and its camera subpath is the path tracer's walk
# with the same random numbers, committing the same wavelength: the same
# pixels as the path tracer's, bit for bit (a wavelength pdf counted twice or
# not at all, or a bin drawn elsewhere, moves them).
P=(render "$DATA/scenes/prism.scene" --backend cpu --mode ml --width 64 --height 8 --spp 32 --seed 5 --quiet)
"$BIN" "${P[@]}" --integrator bdpt -o "$T/pb.exr"
"$BIN" "${P[@]}" --integrator path -o "$T/pp.exr"
check "prism, bdpt: not black" below 1e-3 "$(iinfo --stats "$T/pb.exr" | sed -n 's/^ *Stats Avg: *//p' | awk '{print $1 + $2 + $3}')"
check "prism: bdpt's pixels are the path tracer's" same_pixels "$T/pb.exr" "$T/pp.exr"

# Hero wavelengths: the same paths as truth (the hero set has RNG dimensions
# of its own), each connected path shaded at its sample's four wavelengths;
# against truth per pixel within the hero lanes' noise. Measured (cornell,
# 32 x 32, 8 spp, seed 5): hero against truth 0.077 (the path tracer's hero
# against its truth alike), truth against truth at another seed 0.22; a lane
# weighed wrong by its count (4) or its density moves every pixel by more
# than the bound 0.15. Shown failing on broken builds (host/cpu/refcpu_shade.c
# hero_path): a lane weighed over 3 lanes for 4, 0.41; its density without its
# factor 1 - y^2, 0.21.
H=(render "$CORNELL" --backend cpu --integrator bdpt --width 32 --height 32 --seed 5 --spp 8 --quiet)
"$BIN" "${H[@]}" --mode hero -o "$T/h.exr"
check "hero: exit 0" test $? -eq 0
"$BIN" "${H[@]}" --mode truth -o "$T/t.exr"
check "hero: other pixels than truth's" other_pixels "$T/h.exr" "$T/t.exr"
check "hero against truth: mean relative difference below 0.15" below "$(relavg "$T/h.exr" "$T/t.exr")" 0.15

no_bdpt() { # no_bdpt NAME PATTERN ARGS...: exit 2, PATTERN on stderr, no output
    local what=$1 why=$2
    shift 2
    rm -f "$T/no.exr"
    "$BIN" render "$@" --integrator bdpt --width 8 --height 8 --spp 1 -o "$T/no.exr" 2> "$T/no.err"
    check "$what: exit 2" test $? -eq 2
    check "$what: says why ($why)" grep -q "$why" "$T/no.err"
    check "$what: nothing written" test ! -e "$T/no.exr"
}
no_bdpt "coated" "'coated' picks one of its terms" "$DATA/scenes/coated.scene" --backend cpu
no_bdpt "environment map" "background is no light a subpath starts from yet" "$DATA/scenes/envmap.scene" --backend cpu
finish
