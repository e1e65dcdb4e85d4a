#!/bin/bash
# Error against time of the three integrators (docs/BDPT.md): path, light and
# bdpt tracing on the Cornell box and the caustic scenes (water_caustic,
# lamp_room), on the OpenCL backend (PoCL), each at a few sample counts with
# the integrators alternating (path, light, bdpt, path, ...) so that a shared
# machine's load falls on all three alike, and against a long bdpt render of
# the same scene on a seed of its own (bdpt is unbiased and equals the path
# tracer within its noise, tests/test_bdpt_converge.c).
#
# Time is the render stage's (--json stages.render_s: no loading, tables
# or kernel build); the machine's other jobs stretch it, which the
# alternation spreads over the three; a sample's cost is the slope between
# the smallest and largest sample count. Error: the mean absolute difference from the
# reference over every pixel and channel (linear XYZ-derived sRGB, oiiotool
# --diff), relative to the reference's mean, and the mean CIEDE2000
# (specmip compare). At equal time t, an unbiased integrator's error falls
# as 1/sqrt(t), so integrator i at the path tracer's time has the error
# e_i sqrt(c_i / c_path) (c the cost of a sample): the summary prints that
# ratio. Then ml against truth inside bdpt: the cost of a sample in each and
# ml's mean dE00 from truth on the same paths.
# usage: bench/bdpt_error_time.sh [SPECMIP] [OUT] [REFERENCE_SPP] [SIZE] [SPP...]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$root/build/specmip}
out=${2:-bench-out}
rspp=${3:-1024}
size=${4:-48}
shift $(($# < 4 ? $# : 4))
budgets=${*:-4 16 64}
mkdir -p "$out"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
scenes="cornell water_caustic lamp_room"
# render SCENE ARGS...: prints the render stage's seconds (--json render_s:
# no loading, tables or kernel build)
render() {
    local s=$1
    shift
    "$bin" render "$root/scenes/$s.scene" --width "$size" --height "$size" --quiet \
        --backend opencl --json "$@" 2> /dev/null | jq '.stages.render_s'
}
rel() { oiiotool "$1" "$2" --diff 2> /dev/null | awk '/Mean error/ { print $4; exit }'; }
avg() { oiiotool "$1" --printstats | awk '/Stats Avg/ { print ($3 + $4 + $5) / 3; exit }'; }
de() { "$bin" compare "$1" "$2" --json | sed 's/.*"mean": \([0-9.e+-]*\).*/\1/'; }
csv="$out/bdpt_error_time.csv"
echo "scene,integrator,spp,render_s,rel_mae,mean_de00" > "$csv"
for s in $scenes; do
    render "$s" --mode ml --integrator bdpt --spp "$rspp" --seed 7777 -o "$T/$s-ref.exr" > /dev/null
    m=$(avg "$T/$s-ref.exr")
    for n in $budgets; do
        for i in path light bdpt; do
            c=$(render "$s" --mode ml --integrator $i --spp "$n" --seed 5 -o "$T/$i.exr")
            e=$(rel "$T/$i.exr" "$T/$s-ref.exr")
            echo "$s,$i,$n,$c,$(awk -v e="$e" -v m="$m" 'BEGIN { print e / m }'),$(de "$T/$s-ref.exr" "$T/$i.exr")" >> "$csv"
        done
    done
done
# ml against truth inside bdpt, alternating, at the largest count
big=${budgets##* }
mcsv="$out/bdpt_ml_truth.csv"
echo "scene,mode,spp,render_s,de00_ml_vs_truth" > "$mcsv"
for s in $scenes; do
    for rep in 1 2; do
        for md in truth ml; do
            c=$(render "$s" --mode $md --integrator bdpt --spp "$big" --seed 5 -o "$T/$md.exr")
            d=0
            [ $md = ml ] && d=$(de "$T/truth.exr" "$T/ml.exr")
            echo "$s,$md,$big,$c,$d" >> "$mcsv"
        done
    done
done
cat "$csv" "$mcsv"
python3 "$root/bench/bdpt_error_time_summary.py" "$csv" "$mcsv"
cpu=$(awk -F: '/model name/ { sub(/^ */, "", $2); print $2; exit }' /proc/cpuinfo)
gnuplot -e "data='$csv'; out='$out/bdpt_error_time.png'; title='$cpu, PoCL, ${size}x$size, reference bdpt $rspp spp; load $(cut -d' ' -f1-3 /proc/loadavg)'" - << 'GP'
set terminal pngcairo size 1200,380
set output out
set datafile separator ","
set multiplot layout 1,3 title title
set logscale xy
set xlabel "render seconds"
set ylabel "mean |error| / mean (relative)"
set grid
set key top right
set title "cornell" noenhanced
plot for [i in "path light bdpt"] "< grep ^cornell,".i.", ".data using 4:5 with linespoints title i
set title "water_caustic" noenhanced
plot for [i in "path light bdpt"] "< grep ^water_caustic,".i.", ".data using 4:5 with linespoints title i
set title "lamp_room" noenhanced
plot for [i in "path light bdpt"] "< grep ^lamp_room,".i.", ".data using 4:5 with linespoints title i
unset multiplot
GP
echo "bdpt_error_time.sh: $csv, $mcsv, $out/bdpt_error_time.png"
