#!/bin/bash
# specmip render --integrator bdpt (the CPU reference): a render of the Cornell
# box that records its integrator and gives the same pixels again, and not the
# light tracer's; what it refuses, each with its reason, exit 2 and nothing
# written: hero wavelengths, a type whose vertex picks its term (coated),
# dispersive glass. The OpenCL kernel against this reference is
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

no_bdpt() { # no_bdpt NAME PATTERN ARGS...: exit 2, PATTERN on stderr, no output
    local what=$1 why=$2
    shift 2
    rm -f "$T/no.exr"
    "$BIN" render "$@" --integrator bdpt --width 8 --height 8 --spp 1 -o "$T/no.exr" 2> "$T/no.err"
    check "$what: exit 2" test $? -eq 2
    check "$what: says why ($why)" grep -q "$why" "$T/no.err"
    check "$what: nothing written" test ! -e "$T/no.exr"
}
no_bdpt "hero mode" "hero wavelengths" "$CORNELL" --backend cpu --mode hero
no_bdpt "coated" "'coated' picks one of its terms" "$DATA/scenes/coated.scene" --backend cpu
no_bdpt "dispersive glass" "wavelength" "$DATA/scenes/prism.scene" --backend cpu
finish
