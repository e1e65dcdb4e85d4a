#!/bin/bash
# Error against time of the three integrators (docs/BDPT.md): path, light and
# bdpt tracing on the Cornell box and the caustic scenes (water_caustic,
# lamp_room), on the OpenCL backend (PoCL), each at a few sample counts and
# two seeds with the integrators alternating (path, light, bdpt, path, ...),
# against a long bdpt reference: the mean of REF_SEEDS renders of
# REFERENCE_SPP samples on seeds of their own (bdpt is unbiased and equals the
# path tracer within its noise, tests/test_bdpt_converge.c). The references
# are kept in OUT/ref and reused, so they can be made first (REF_ONLY=1),
# each scene with a sample count of its own.
#
# Cost: each render's process CPU time (user + sys, /usr/bin/time; PoCL's
# threads included), not its wall time, which the machine's other jobs
# stretch; a sample's cost from a long render against one of 1 sample (the
# loading, tables and kernel build cancel). The render
# stage's wall time (--json stages.render_s) is kept beside it.
# Error: the mean absolute difference from the reference over every pixel and
# channel of the linear sRGB image, relative to the reference's mean, and the
# mean CIEDE2000 (specmip compare); and the same relative error split
# between the pixels whose camera ray meets a dielectric first (a scene
# variant in which the dielectrics emit and nothing else reflects or emits
# marks them) and the rest. At equal time t an unbiased integrator's error
# falls as 1/sqrt(t), so integrator i at the path tracer's time has the error
# e_i sqrt(c_i / c_path): the summary prints that ratio. Then ml against
# truth inside bdpt: ml's mean dE00 from truth on the same paths.
# usage: bench/bdpt_error_time.sh [SPECMIP] [OUT] [REFERENCE_SPP] [SIZE] [SPP...]
# environment: SCENES (default "water_caustic lamp_room cornell"), REF_SEEDS
# (default 4), REF_ONLY=1 (make the references and stop), COST_ONLY=1 (the
# references and the cost of a sample), COST_SPP, COST_REPS (see below)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$root/build/specmip}
out=${2:-bench-out}
rspp=${3:-8192}
size=${4:-24}
shift $(($# < 4 ? $# : 4))
budgets=${*:-16 64 256}
scenes=${SCENES:-water_caustic lamp_room cornell}
nref=${REF_SEEDS:-4}
py=$root/build/pyenv/bin/python
[ -x "$py" ] || py=python3
mkdir -p "$out/ref"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
# render SCENE_FILE OUT.exr ARGS...: prints "cpu_s render_s" (the process's
# user + sys seconds, the render stage's wall seconds)
render() {
    local f=$1 o=$2
    shift 2
    local r
    r=$(/usr/bin/time -f '%U %S' -o "$T/time" "$bin" render "$f" --width "$size" \
        --height "$size" --quiet --backend opencl --json -o "$o" "$@" 2> /dev/null |
        jq '.stages.render_s')
    awk -v r="$r" '{ printf "%.3f %s\n", $1 + $2, r }' "$T/time"
}
de() { "$bin" compare "$1" "$2" --json | sed 's/.*"mean": \([0-9.e+-]*\).*/\1/'; }
# the reference of scene S: the mean of its seeds' renders
reference() {
    local s=$1 k files=()
    for k in $(seq 1 "$nref"); do
        local f="$out/ref/$s-$size-$rspp-$k.exr"
        if [ ! -s "$f" ]; then
            render "$root/scenes/$s.scene" "$T/r.exr" --mode ml --integrator bdpt \
                --spp "$rspp" --seed $((7776 + k)) > "$out/ref/$s-$size-$rspp-$k.time"
            mv "$T/r.exr" "$f"
        fi
        files+=("$f")
    done
    oiiotool "${files[@]}" $(printf -- '--add %.0s' $(seq 2 "$nref")) --divc "$nref" \
        -o "$out/ref/$s-ref.exr"
}
# the mask of scene S: its dielectrics emit 1, nothing else reflects or emits
# (black where it has none)
mask() {
    local s=$1
    if ! grep -q '^material .* dielectric' "$root/scenes/$s.scene"; then
        oiiotool "$out/ref/$s-ref.exr" --mulc 0 -o "$out/ref/$s-mask.exr"
        return
    fi
    cp -r "$root/scenes" "$T/scenes"
    awk '$1 == "material" && $3 == "dielectric" { print "material", $2, "reflect equal 0 emit equal 1"; next }
         $1 == "material" { print "material", $2, "reflect equal 0"; next }
         $1 == "light" { next } { print }' "$root/scenes/$s.scene" > "$T/scenes/$s-mask.scene"
    render "$T/scenes/$s-mask.scene" "$out/ref/$s-mask.exr" --mode truth --spp 16 --seed 1 > /dev/null
    rm -rf "$T/scenes"
}
for s in $scenes; do
    [ -s "$out/ref/$s-ref.exr" ] || reference "$s"
    [ -s "$out/ref/$s-mask.exr" ] || mask "$s"
done
[ "${REF_ONLY:-0}" = 1 ] && exit 0
# the cost of a sample: a render of many samples against one of 1 (the
# process's fixed CPU time, about 1 s, cancels), alternating, COST_REPS times
# (default 2); COST_SPP the long renders' counts of path, light and bdpt
ccsv="$out/bdpt_cost.csv"
echo "scene,integrator,spp,cpu_s" > "$ccsv"
read -r np nl nb <<< "${COST_SPP:-8192 4096 2048}"
for s in $scenes; do
    for rep in $(seq 1 "${COST_REPS:-2}"); do
        for i in path light bdpt; do
            case $i in path) n=$np ;; light) n=$nl ;; bdpt) n=$nb ;; esac
            for m in 1 $n; do
                read -r c w < <(render "$root/scenes/$s.scene" "$T/c.exr" --mode ml --integrator $i \
                    --spp $m --seed $rep)
                echo "$s,$i,$m,$c" >> "$ccsv"
            done
        done
    done
done
[ "${COST_ONLY:-0}" = 1 ] && exit 0
csv="$out/bdpt_error_time.csv"
echo "scene,integrator,spp,seed,cpu_s,render_s,rel_mae,rel_mae_dielectric,rel_mae_rest,mean_de00" > "$csv"
for s in $scenes; do
    ref="$out/ref/$s-ref.exr"
    # a first render of each integrator fills PoCL's kernel cache
    for i in path light bdpt; do
        render "$root/scenes/$s.scene" "$T/w.exr" --mode ml --integrator $i --spp 1 > /dev/null
    done
    for n in $budgets; do
        for seed in 5 6; do
            for i in path light bdpt; do
                read -r c w < <(render "$root/scenes/$s.scene" "$T/$i.exr" --mode ml \
                    --integrator $i --spp "$n" --seed $seed)
                e=$("$py" "$root/bench/bdpt_error_time_summary.py" --error "$T/$i.exr" "$ref" \
                    "$out/ref/$s-mask.exr")
                echo "$s,$i,$n,$seed,$c,$w,$e,$(de "$ref" "$T/$i.exr")" >> "$csv"
            done
        done
    done
done
# ml against truth inside bdpt at the largest count
big=${budgets##* }
mcsv="$out/bdpt_ml_truth.csv"
echo "scene,mode,spp,cpu_s,render_s,de00_ml_vs_truth" > "$mcsv"
for s in $scenes; do
    for md in truth ml; do
        read -r c w < <(render "$root/scenes/$s.scene" "$T/$md.exr" --mode $md --integrator bdpt \
            --spp "$big" --seed 5)
        d=0
        [ $md = ml ] && d=$(de "$T/truth.exr" "$T/ml.exr")
        echo "$s,$md,$big,$c,$w,$d" >> "$mcsv"
    done
done
cat "$csv" "$mcsv"
refs=()
for s in $scenes; do refs+=("$out/ref/$s"); done
"$py" "$root/bench/bdpt_error_time_summary.py" "$csv" "$mcsv" "$ccsv" "$nref" "${refs[@]}"
cpu=$(awk -F: '/model name/ { sub(/^ */, "", $2); print $2; exit }' /proc/cpuinfo)
pcsv="${csv%.csv}_plot.csv"
gnuplot -e "data='$pcsv'; out='$out/bdpt_error_time.png'; title='$cpu, PoCL, ${size}x$size, ml; against the mean of $nref long bdpt renders; rendering CPU time (samples x process CPU time a sample); load $(cut -d' ' -f1-3 /proc/loadavg)'" - << 'GP'
set terminal pngcairo size 1400,380
set output out
set datafile separator ","
set multiplot layout 1,4 title title noenhanced
set logscale xy
set xlabel "CPU seconds"
set ylabel "mean |error| / mean (relative)"
set grid
set key bottom left
set title "water_caustic, all pixels" noenhanced
plot for [i in "path light bdpt"] "< grep ^water_caustic,".i.", ".data using 3:4 with linespoints title i
set title "water_caustic, seen through the water" noenhanced
plot for [i in "path light bdpt"] "< grep ^water_caustic,".i.", ".data using 3:5 with linespoints title i
set title "lamp_room" noenhanced
plot for [i in "path light bdpt"] "< grep ^lamp_room,".i.", ".data using 3:4 with linespoints title i
set title "cornell" noenhanced
plot for [i in "path light bdpt"] "< grep ^cornell,".i.", ".data using 3:4 with linespoints title i
unset multiplot
GP
echo "bdpt_error_time.sh: $csv, $mcsv, $ccsv, $out/bdpt_error_time.png"
