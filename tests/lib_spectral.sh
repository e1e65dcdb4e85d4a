# Shared by the spectral-output tests (sourced after lib_cli.sh): the
# scene, the checker tests/spectral_check.cpp, the per-mode tolerances and
# modes_on BACKEND, which renders every spectral mode on BACKEND and checks
# each file.
CHECK=${SPECTRAL_CHECK:-$PWD/spectral_check}
SCENE=$ROOT/tests/data/scenes/lamp_wall.scene
CMF=$DATA/spectra/cie1931_2deg_cmf_1nm.csv
F11=$DATA/spectra/illuminant_F11.csv
LAMP=(2 8) # a pixel on the lamp
PY=${SPECMIP_PYTHON:-python3}

# spectral NAME CHECKS... -- RENDER-ARGS...: renders NAME.exr and
# NAME.spectral.exr, then runs the checks on them.
spectral() {
    local name=$1 checks=()
    shift
    while [ "$1" != "--" ]; do checks+=("$1"); shift; done
    shift
    "$BIN" render "$SCENE" --quiet -o "$T/$name.exr" -o "$T/$name.spectral.exr" "$@" 2> "$T/err"
    local rc=$?
    check "$name: render exit 0 (got $rc: $(tail -1 "$T/err"))" test $rc -eq 0
    local c=("${checks[@]//@XYZ@/$T/$name.exr}")
    "$CHECK" "$T/$name.spectral.exr" --cmf "$CMF" "${c[@]}" > "$T/check" 2>&1
    rc=$?
    sed 's/^/  /' "$T/check"
    check "$name: spectral file checks" test $rc -eq 0
}

# Tolerances, as fractions (float32 keeps ~6e-8 relative per operation):
# EXACT: the file's bins are the film's lanes moved, averaged or copied
#   (ref, ml, truth at 1 nm) and the film's XYZ weights are the bins' CMF
#   integrals, so only float rounding over a few hundred terms differs
#   (measured below 2e-7).
EXACT=1e-5
# TRUTH5: truth's film weights every 1 nm bin by its own CMF; its 5 nm file
#   keeps the bins' means, which lose the covariance of spectrum and CMF
#   inside a bin (measured 4e-4 on this scene).
TRUTH5=1e-3
# MLC: a spike's film weight is the CMF's mean over its 1 nm profile; in the file its
#   energy is spread over its 5 nm bin, weighted by the bin's mean CMF: up to
#   several percent of a line (the CMFs change that much over 5 nm), less
#   for the image (measured 0.7%).
MLC=2e-2
# HERO: the film weights a lane by the CMF at its wavelength, the file by
#   its bin's mean CMF, so the two agree in expectation only: the image mean
#   at 16 spp (seed 1) differs by sampling noise (measured 3e-4; a lane put
#   one bin off moves it 9e-3). The lamp pixel's radiance at 256 spp carries
#   hero's noise on F11's 1 nm lines: over seeds 1-4 it was off by 1.4-6.5 %
#   (sigma about 5 %, 2.5 % at 1024 spp, centred on the lamp), so 0.2 is four
#   sigma; a wrong lane count or bin width is off by 25 % or more.
HERO=3e-3
HERO_LAMP=0.2

modes_on() {
    local be=$1
    spectral "ref-$be" --xyz @XYZ@ $EXACT --lamp "$F11" 1000 "${LAMP[@]}" $EXACT -- \
        --mode ref --backend $be
    # ml shades the lamp at a coarser level: its energy, not its 5 nm shape
    spectral "ml-$be" --xyz @XYZ@ $EXACT --energy "$F11" 1000 "${LAMP[@]}" $EXACT -- \
        --mode ml --backend $be
    spectral "truth-$be" --xyz @XYZ@ $TRUTH5 --lamp "$F11" 1000 "${LAMP[@]}" $EXACT -- \
        --mode truth --backend $be
    spectral "truth1-$be" --xyz @XYZ@ $EXACT --lamp "$F11" 1000 "${LAMP[@]}" $EXACT -- \
        --mode truth --spectral-nm 1 --backend $be
    spectral "mlc-$be" --xyz-mean @XYZ@ $MLC --energy "$F11" 1000 "${LAMP[@]}" $EXACT -- \
        --mode mlc --backend $be
    spectral "hero-$be" --xyz-mean @XYZ@ $HERO -- --mode hero --backend $be
    spectral "hero256-$be" --energy "$F11" 1000 "${LAMP[@]}" $HERO_LAMP -- \
        --mode hero --spp 256 --backend $be
}
