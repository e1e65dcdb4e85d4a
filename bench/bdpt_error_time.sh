#!/bin/bash
# Error against time of the three integrators (docs/BDPT.md): path, light and
# bdpt tracing on the Cornell box and on a caustic scene (scenes/glass.scene
# with its rough block made smooth: glass blocks and a glass sphere under an
# area light, whose caustics a camera path finds through a delta vertex
# only), each rendered for each time budget and compared with a long bdpt
# render of the same scene on seeds of its own (bdpt is unbiased and equals
# the path tracer within its noise, tests/test_bdpt_converge.c). Writes the
# RMS error (linear sRGB, oiiotool --diff) and the mean CIEDE2000 (specmip
# compare) to OUT/bdpt_error_time.csv and the chart OUT/bdpt_error_time.png.
# usage: bench/bdpt_error_time.sh [SPECMIP] [OUT] [REFERENCE_SECONDS] [BACKEND] [SECONDS...]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$root/build/specmip}
out=${2:-bench-out}
rsec=${3:-120}
backend=${4:-opencl}
shift $(( $# < 4 ? $# : 4 ))
budgets=${*:-1 2 4 8}
mkdir -p "$out"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
sed 's/^material rough .*/material rough     dielectric ior 1.5/' "$root/scenes/glass.scene" \
    > "$T/caustic.scene"
cp "$root/scenes/materials_sphere.ply" "$T/"
cp "$root/scenes/cornell.scene" "$T/cornell.scene"
run() { "$bin" render "$T/$1.scene" --mode ml --width 64 --height 64 --quiet --backend "$backend" "${@:2}"; }
rms() { oiiotool "$1" "$2" --diff 2>/dev/null | awk '/RMS error/ { print $4; exit }'; }
de() { "$bin" compare "$2" "$1" --json | sed 's/.*"mean": \([0-9.e+-]*\).*/\1/'; }
spp() { oiiotool --info -v "$1" | awk -F: '/samplesPerPixel:/ { print $2 + 0; exit }'; }
csv="$out/bdpt_error_time.csv"
echo "scene,integrator,seconds,spp,rms,mean_de00" > "$csv"
for scene in cornell caustic; do
  run "$scene" --integrator bdpt --time "$rsec" --seed 7777 -o "$T/$scene-ref.exr"
  for s in $budgets; do
    for i in path light bdpt; do
      run "$scene" --integrator "$i" --time "$s" --seed 5 -o "$T/$i.exr"
      echo "$scene,$i,$s,$(spp "$T/$i.exr"),$(rms "$T/$i.exr" "$T/$scene-ref.exr"),$(de "$T/$i.exr" "$T/$scene-ref.exr")" >> "$csv"
    done
  done
done
cat "$csv"
awk -F, 'NR > 1 { r[$1 "," $2 "," $3] = $5; if ($2 == "bdpt") k[++n] = $1 "," $3 }
  END { for (i = 1; i <= n; i++) printf "%s s: path / bdpt = %.2f x the RMS, light / bdpt = %.2f x\n",
        k[i], r[substr(k[i], 1, index(k[i], ",")) "path," substr(k[i], index(k[i], ",") + 1)] / r[substr(k[i], 1, index(k[i], ",")) "bdpt," substr(k[i], index(k[i], ",") + 1)],
        r[substr(k[i], 1, index(k[i], ",")) "light," substr(k[i], index(k[i], ",") + 1)] / r[substr(k[i], 1, index(k[i], ",")) "bdpt," substr(k[i], index(k[i], ",") + 1)] }' "$csv"
cpu=$(awk -F: '/model name/ { sub(/^ */, "", $2); print $2; exit }' /proc/cpuinfo)
gnuplot -e "data='$csv'; out='$out/bdpt_error_time.png'; title='$cpu, $backend, 64x64, reference bdpt $rsec s'" - << 'GP'
set terminal pngcairo size 900,380
set output out
set datafile separator ","
set multiplot layout 1,2 title title
set logscale xy
set xlabel "seconds"
set ylabel "RMS error (linear sRGB)"
set grid
set key top right
set title "cornell"
plot for [i in "path light bdpt"] "< grep ^cornell,".i.", ".data using 3:5 with linespoints title i
set title "caustic"
plot for [i in "path light bdpt"] "< grep ^caustic,".i.", ".data using 3:5 with linespoints title i
unset multiplot
GP
echo "bdpt_error_time.sh: $csv, $out/bdpt_error_time.png"
