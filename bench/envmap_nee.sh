#!/bin/bash
# The environment map's next-event estimation against uniform sphere
# sampling at equal time (docs/RESULTS.md, "Environment map sampling"): a
# diffuse floor and sphere under scenes/sunsky.hdr (a 3-degree sun 4000 times
# the zenith), rendered on the CPU reference for SECONDS each, the map
# sampled by its distribution (luminance x sin theta) and uniformly over the
# sphere (SPECMIP_BENCH_ENV_UNIFORM=1, light samples and MIS alike), each
# against a long OpenCL render of the same scene; prints the RMS error of
# each (oiiotool --diff, linear sRGB) and their ratio.
# usage: bench/envmap_nee.sh [SPECMIP] [SECONDS] [REFERENCE_SPP]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$root/build/specmip}
secs=${2:-20}
rspp=${3:-4096}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cat > "$T/nee.scene" <<SCENE
image 96 64
camera position 0 1.1 -4  direction 0 -0.2 1  fov 40
spectrum grey equal
material floor reflect grey 0.5
background map $root/scenes/sunsky.hdr rotate 200
quad floor  -60 0 -60  -60 0 60  60 0 60  60 0 -60
mesh $root/scenes/materials_sphere.ply material floor scale 0.7 translate 0 0.7 0.5
SCENE
run() { "$bin" render "$T/nee.scene" --mode rgb --quiet "$@"; }
run --spp "$rspp" -o "$T/ref.exr"
rms() { oiiotool "$1" "$T/ref.exr" --diff 2>/dev/null | awk '/RMS error/ { print $4; exit }'; }
run --backend cpu --time "$secs" -o "$T/nee.exr"
SPECMIP_BENCH_ENV_UNIFORM=1 run --backend cpu --time "$secs" -o "$T/uni.exr"
spp() { oiiotool --info -v "$1" | awk -F: '/samplesPerPixel:/ { print $2 + 0; exit }'; }
e1=$(rms "$T/nee.exr") e2=$(rms "$T/uni.exr")
echo "map's distribution: $(spp "$T/nee.exr") spp in ${secs} s, RMS error $e1"
echo "uniform sphere:     $(spp "$T/uni.exr") spp in ${secs} s, RMS error $e2"
awk -v a="$e1" -v b="$e2" 'BEGIN { printf "uniform / distribution: %.2f x the error\n", b / a }'
