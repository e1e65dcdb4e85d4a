#!/usr/bin/env bash
# mlc against the 1 nm truth on the same paths (specmip compare defaults: mean
# and p99 ΔE00 after the 5x5 blur), beside ml. Its levels come from the
# composite representation's error against truth, so where the two modes
# shade at nearly the same levels mlc is at least as close to truth as ml
# (its lanes hold what the bins smear). Where the lanes carry the whole light
# (narrowline) ml's pretest sends every path to 1 nm, which is truth, while
# mlc keeps the threshold at 20 bins.
source "$(dirname "$0")/lib_cli.sh"
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$PWD/pocl-cache}
S=48 SPP=16

render() { # scene mode out [options...]
    local scene=$1 mode=$2 out=$3; shift 3
    "$BIN" render "$ROOT/scenes/$scene.scene" --mode "$mode" --width $S --height $S --spp $SPP \
        --seed 1 --quiet -o "$out" "$@" 2>"$T/err" || { cat "$T/err" >&2; return 1; }
}
de() { # truth test field -> the field of specmip compare's JSON
    "$BIN" compare "$1" "$2" --json | jq -r ".$3"
}
# at_most WHAT a b factor: a <= b * factor
at_most() {
    python3 -c 'import sys; a, b, f = map(float, sys.argv[1:]); sys.exit(0 if a <= b * f else 1)' \
        "$2" "$3" "$4" && ok || bad "$1: $2 > $3 x $4"
}

# The margin: on cornell_spiky and metameric at T = 1 the two modes' level
# shares differ by a few per cent of the paths (ml's pretest is of its bins,
# mlc's of its composite), so their arithmetic is not the same on every path;
# 10 % covers that. mlc's earlier level choice was 1.3 to 1.8 times ml's error,
# and on narrowline (p99 2.0 at both thresholds) missed the threshold.
for scene in cornell_spiky metameric narrowline; do
    render $scene truth "$T/truth.exr" || { bad "$scene truth render"; continue; }
    for t in 1 2; do
        render $scene ml "$T/ml.exr" --threshold $t || { bad "$scene ml render"; continue; }
        render $scene mlc "$T/mlc.exr" --threshold $t || { bad "$scene mlc render"; continue; }
        for f in mean p99; do
            ml=$(de "$T/truth.exr" "$T/ml.exr" $f)
            mlc=$(de "$T/truth.exr" "$T/mlc.exr" $f)
            # the threshold is a promise against truth: mlc keeps it
            at_most "$scene T=$t mlc $f within the threshold" "$mlc" $t 1
            if [ $t = 1 ] && [ $scene != narrowline ]; then
                at_most "$scene T=$t mlc $f against ml's" "$mlc" "$ml" 1.1
            fi
        done
    done
done

# At T = 2 mlc takes 20-bin levels where ml cannot (the lines smear); held to
# 40 bins at most it is again as close to truth as ml at T = 2.
for scene in cornell_spiky metameric; do
    render $scene truth "$T/truth.exr" && render $scene ml "$T/ml.exr" --threshold 2 &&
        render $scene mlc "$T/mlc.exr" --threshold 2 --coarsest-level 2 ||
        { bad "$scene renders"; continue; }
    for f in mean p99; do
        at_most "$scene T=2 coarsest level 1 mlc $f against ml's" \
            "$(de "$T/truth.exr" "$T/mlc.exr" $f)" "$(de "$T/truth.exr" "$T/ml.exr" $f)" 1.1
    done
done
finish
