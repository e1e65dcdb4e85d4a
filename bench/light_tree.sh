#!/bin/bash
# The light tree against the power selection at equal time (docs/LIGHT_TREE.md):
# the many-light scene of tools/lamp_street.sh (12000 emitting triangles of
# mixed power), rendered for each time budget with --light-sampler power and
# tree, each against a long tree render of the same scene; writes the
# error of each (mean CIEDE2000 by `specmip compare`, RMS of linear sRGB by
# oiiotool --diff) to OUT/light_tree.csv and the chart OUT/light_tree.png.
# usage: bench/light_tree.sh [SPECMIP] [OUT] [REFERENCE_SPP] [BACKEND] [SECONDS...]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$root/build/specmip}
out=${2:-bench-out}
rspp=${3:-1024}
backend=${4:-opencl}
shift $(( $# < 4 ? $# : 4 ))
budgets=${*:-1 2 4 8 16}
mkdir -p "$out"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$root/tools/lamp_street.sh" > "$T/lamps.scene"
run() { "$bin" render "$T/lamps.scene" --mode rgb --width 160 --height 90 --quiet "$@"; }
# the reference on seeds of its own: the budgets' renders must not share its first samples
run --light-sampler tree --spp "$rspp" --seed 7777 -o "$T/ref.exr"
rms() { oiiotool "$1" "$T/ref.exr" --diff 2>/dev/null | awk '/RMS error/ { print $4; exit }'; }
de() { "$bin" compare "$T/ref.exr" "$1" --json | sed 's/.*"mean": \([0-9.e+-]*\).*/\1/'; }
spp() { oiiotool --info -v "$1" | awk -F: '/samplesPerPixel:/ { print $2 + 0; exit }'; }
csv="$out/light_tree.csv"
echo "sampler,seconds,spp,mean_de00,rms" > "$csv"
for s in $budgets; do
  for sampler in power tree; do
    run --backend "$backend" --light-sampler "$sampler" --time "$s" -o "$T/$sampler.exr"
    echo "$sampler,$s,$(spp "$T/$sampler.exr"),$(de "$T/$sampler.exr"),$(rms "$T/$sampler.exr")" >> "$csv"
  done
done
cat "$csv"
awk -F, 'NR > 1 { e[$1 "," $2] = $4; r[$1 "," $2] = $5; if ($1 == "tree") t[++n] = $2 }
  END { for (i = 1; i <= n; i++) printf "%s s: power / tree = %.2f x the mean dE00, %.2f x the RMS\n",
        t[i], e["power," t[i]] / e["tree," t[i]], r["power," t[i]] / r["tree," t[i]] }' "$csv"
cpu=$(awk -F: '/model name/ { sub(/^ */, "", $2); print $2; exit }' /proc/cpuinfo)
gnuplot -e "data='$csv'; out='$out/light_tree.png'; title='$cpu, $backend, 160x90, reference $rspp spp'" - << 'GP'
set terminal pngcairo size 900,380
set output out
set datafile separator ","
set multiplot layout 1,2 title title
set logscale xy
set xlabel "seconds"
set grid
set key top right
set ylabel "mean CIEDE2000"
plot "< grep ^power ".data using 2:4 with linespoints title "power", \
     "< grep ^tree ".data using 2:4 with linespoints title "light tree"
set ylabel "RMS error (linear sRGB)"
plot "< grep ^power ".data using 2:5 with linespoints title "power", \
     "< grep ^tree ".data using 2:5 with linespoints title "light tree"
unset multiplot
GP
echo "light_tree.sh: $csv, $out/light_tree.png"
