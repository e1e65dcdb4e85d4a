#!/usr/bin/env bash
# The scale benchmark: procedural meshes (tools/gen_meshes.py --scale: a bumpy
# sphere and torus seen from inside, random triangle soups) from 1k triangles
# up, and every bundled scene. Per case: import and BVH build time, SAH cost
# and nodes (render --json), the render's paths/s and peak memory, and traversal
# alone on the render's own rays (bench --rays: closest-hit and shadow rays/s,
# with Embree's beside them when this build has it). Writes OUT/scale.csv and
# OUT/scale.png (gnuplot) and prints the table. A render whose timed part
# included a PoCL kernel compile (render --json's compiled_during_timing; the
# build stage's warm-up launches are meant to leave none) is flagged: a WARNING
# on stderr, "!" after its Mpaths/s and 1 in the CSV's compiled_during_timing.
# A benchmark, not a test: run it on a quiet machine; the CSV names the CPU.
#
# usage: bench/scale.sh [OUT]            (default scale-out)
# environment (defaults in brackets):
#   SPECMIP       the binary [build/specmip]
#   SCALE_SHAPES  procedural shapes, of sphere torus soup [sphere soup]
#   SCALE_SIZES   triangle counts [1000 10000 100000 1000000]; up to 4000000 works
#                 (a 4M soup takes ~1 GB of PLY and a minute to write)
#   SCALE_SCENES  1: the bundled scenes too, 0: not [1]
#   SCALE_RENDER  WxH spp of the timed render [128x128 16]
#   SCALE_RAYS    WxH spp whose rays bench --rays replays [128x128 1]
#   SCALE_REPEAT  replays per ray kind, the fastest counts [3]
#   SCALE_EMBREE  1: replay through Embree too (needs a build with it), 0: not,
#                 auto: when the binary has it [auto]
#   SCALE_DEVICE  OpenCL device [0]
# The default run takes a few minutes on 2 cores.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${SPECMIP:-$here/build/specmip}
out=${1:-scale-out}
shapes=${SCALE_SHAPES:-sphere soup}
sizes=${SCALE_SIZES:-1000 10000 100000 1000000}
scenes=${SCALE_SCENES:-1}
read -r rsize rspp <<< "${SCALE_RENDER:-128x128 16}"
read -r ysize yspp <<< "${SCALE_RAYS:-128x128 1}"
repeat=${SCALE_REPEAT:-3}
embree=${SCALE_EMBREE:-auto}
device=${SCALE_DEVICE:-0}
for tool in jq python3 gnuplot; do
  command -v "$tool" > /dev/null || { echo "scale.sh: needs $tool (tools/setup.sh installs it)" >&2; exit 2; }
done
[ -x /usr/bin/time ] || { echo "scale.sh: needs GNU time (tools/setup.sh installs it)" >&2; exit 2; }
[ -x "$bin" ] || { echo "scale.sh: no binary at $bin" >&2; exit 2; }
for s in $shapes; do
  case $s in sphere | torus | soup) ;; *) echo "scale.sh: unknown shape '$s' (sphere torus soup)" >&2; exit 2 ;; esac
done
for n in $sizes; do
  [[ $n =~ ^[0-9]+$ ]] && [ "$n" -ge 16 ] || { echo "scale.sh: SCALE_SIZES: '$n' is not a count >= 16" >&2; exit 2; }
done
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$here/build/pocl-cache}
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
if [ "$embree" = auto ]; then
  embree=0
  "$bin" bench --rays default --size 8x8 --repeat 1 --embree --json > /dev/null 2>&1 && embree=1
fi
ebflag=()
[ "$embree" = 1 ] && ebflag=(--embree)
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)

csv=$out/scale.csv
part=$csv.part
echo "case,triangles,import_s,bvh_s,sah_cost,bvh_nodes,bvh_threads,render_mpaths_s,peak_rss_mb,\
rays_closest,rays_shadow,specmip_closest_mrays_s,specmip_shadow_mrays_s,embree_closest_mrays_s,\
embree_shadow_mrays_s,ratio_closest,ratio_shadow,nodes_per_closest_ray,tri_tests_per_closest_ray,\
differ_reference,differ_embree,compiled_during_timing" > "$part"
printf '%-16s %9s %8s %8s %8s %9s%1s %8s %8s %8s %8s %8s\n' case triangles import_s bvh_s sah \
  Mpaths/s "" RSS_MB closest shadow x_embree x_embree
# one case: NAME SCENE
run_case() {
  local name=$1 scene=$2 w h
  w=${rsize%x*} h=${rsize#*x}
  /usr/bin/time -f %M -o "$tmp/rss" "$bin" render "$scene" --width "$w" --height "$h" --spp "$rspp" \
    --device "$device" --json --quiet -o "$tmp/img.exr" > "$tmp/r.json" 2> "$tmp/err" ||
    { echo "scale.sh: $name: render failed:" >&2; cat "$tmp/err" >&2; return 1; }
  "$bin" bench --rays "$scene" --size "$ysize" --rays-spp "$yspp" --repeat "$repeat" --device "$device" \
    --rays-stats "${ebflag[@]}" --json > "$tmp/y.json" 2> "$tmp/err" ||
    { echo "scale.sh: $name: bench --rays failed:" >&2; cat "$tmp/err" >&2; return 1; }
  # a render whose time includes a PoCL compile measured the compiler (render --json)
  local compiled
  compiled=$(jq -r '.compiled_during_timing' "$tmp/r.json")
  [ "$compiled" = true ] &&
    echo "scale.sh: WARNING: $name: PoCL compiled kernels during the timed render: its paths/s include compile time" >&2
  # peak RSS: the render's own figure when it gives one, else GNU time's
  local rss
  rss=$(jq -r --arg t "$(cat "$tmp/rss")" '.peak_rss_bytes // (($t | tonumber) * 1024) | . / 1048576' "$tmp/r.json")
  jq -r -s --arg name "$name" --arg rss "$rss" --arg compiled "$compiled" '
    def v(x): if x == null then "-" else x end;
    def r(a; b): if a == null or b == null or b == 0 then "-" else a / b end;
    .[0] as $r | .[1] as $y |
    [$name, $y.triangles, $r.stages.load_s, $r.stages.bvh_s, v($r.bvh.sah_cost), v($r.bvh.nodes),
     v($r.bvh.threads), $r.paths_per_s / 1e6, ($rss | tonumber), $y.rays_closest, $y.rays_shadow,
     $y.specmip.closest_mrays_s, $y.specmip.shadow_mrays_s, v($y.embree.closest_mrays_s),
     v($y.embree.shadow_mrays_s), r($y.specmip.closest_mrays_s; $y.embree.closest_mrays_s),
     r($y.specmip.shadow_mrays_s; $y.embree.shadow_mrays_s), v($y.specmip.nodes_closest),
     v($y.specmip.tris_closest), $y.reference.closest_differ + $y.reference.shadow_differ,
     (if $y.embree == null then "-" else $y.embree.closest_differ + $y.embree.shadow_differ end),
     (if $compiled == "true" then 1 elif $compiled == "false" then 0 else "-" end)]
    | map(tostring) | join(",")' "$tmp/r.json" "$tmp/y.json" >> "$part"
  tail -1 "$part" | awk -F, '{ printf "%-16s %9d %8.3f %8.3f %8s %9.3f%1s %8.0f %8.3f %8.3f %8s %8s\n",
    $1, $2, $3, $4, $5 == "-" ? "-" : sprintf("%.2f", $5), $8, $22 == 1 ? "!" : "", $9, $12, $13,
    $16 == "-" ? "-" : sprintf("%.3f", $16), $17 == "-" ? "-" : sprintf("%.3f", $17) }'
}

for s in $shapes; do
  for n in $sizes; do
    python3 "$here/tools/gen_meshes.py" --scale "$s" "$n" "$tmp/$s.ply" "$tmp/$s.scene" > /dev/null
    run_case "$s-$n" "$tmp/$s.scene"
    rm -f "$tmp/$s.ply"
  done
done
if [ "$scenes" = 1 ]; then
  for f in "$here"/scenes/*.scene; do
    run_case "$(basename "$f" .scene)" "$f"
  done
fi
mv "$part" "$csv"
{
  echo "# $cpu; $(nproc) cores; $("$bin" --version); render $rsize $rspp spp; rays $ysize $yspp spp;"
  echo "# rays/s: the fastest of $repeat replays; x_embree = specmip/Embree rays/s (closest, shadow)"
} > "$out/scale_meta.txt"

# The chart: triangles against load time, rays/s and memory (procedural cases only)
awk -F, 'NR > 1 && $1 ~ /-[0-9]+$/' "$csv" > "$tmp/proc.csv"
if [ -s "$tmp/proc.csv" ]; then
  gnuplot -e "data='$tmp/proc.csv'; out='$out/scale.png'; shapes='$shapes'; title='$cpu'" - << 'GP'
set terminal pngcairo size 1200,420
set output out
set datafile separator ","
set multiplot layout 1,3 title title
set logscale xy
set format x "10^{%T}"
set xlabel "triangles"
set key top left
set grid
set ylabel "seconds"
set title "import and BVH build"
plot for [s in shapes] sprintf("< grep '^%s-' %s", s, data) using 2:3 with linespoints title s." import", \
     for [s in shapes] sprintf("< grep '^%s-' %s", s, data) using 2:4 with linespoints dt 2 title s." BVH"
set title "traversal, closest-hit rays"
set ylabel "Mrays/s"
set key top right
plot for [s in shapes] sprintf("< grep '^%s-' %s", s, data) using 2:12 with linespoints title s." specmip", \
     for [s in shapes] sprintf("< grep '^%s-' %s", s, data) using 2:14 with linespoints dt 2 title s." Embree"
set title "peak memory"
set ylabel "MB"
set logscale y
set key top left
plot for [s in shapes] sprintf("< grep '^%s-' %s", s, data) using 2:9 with linespoints title s
unset multiplot
GP
fi
echo "scale.sh: $csv, $out/scale.png ($cpu)"
