#!/usr/bin/env bash
# Bitterli's scenes in pbrt-v4 form (the public repository gonsolo/bitterli)
# rendered from their own files and compared with the Tungsten renders beside
# them (docs/VALIDATION_PBRT.md): mean and p99 CIEDE2000 (specmip compare,
# 5 x 5 box blur) and the ratio of mean luminances, in rgb and truth modes,
# with the triangle count, what the load warned about and the render time.
# The references are 1024 or 1280 pixels wide; both sides are compared at
# WIDTH (the reference resized by oiiotool). specmip's paths end by Russian
# roulette, so the files' lowered maxdepth does not apply.
# Usage: bench/pbrt_validate.sh BITTERLI_DIR [SPECMIP] [WIDTH] [SPP] [SCENES...]
#   BITTERLI_DIR: a checkout of https://github.com/gonsolo/bitterli
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
src=${1:?usage: bench/pbrt_validate.sh BITTERLI_DIR [SPECMIP] [WIDTH] [SPP] [SCENES...]}
bin=${2:-$here/build/specmip}
width=${3:-256}
spp=${4:-256}
shift $(( $# < 4 ? $# : 4 ))
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell-box veach-mis veach-bidir coffee)
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$here/build/pocl-cache}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
luma() { oiiotool --stats "$1" 2>/dev/null | awk '/Stats Avg/ { print 0.2126 * $3 + 0.7152 * $4 + 0.0722 * $5 }'; }
echo "# ${width} px wide, $spp spp; CPU: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores (shared)"
echo "| scene | triangles | ignored (warnings) | mode | mean dE00 | p99 dE00 | luminance ratio | time (s) |"
echo "|---|---:|---|---|---:|---:|---:|---:|"
for s in "${scenes[@]}"; do
  d=$src/$s/pbrt
  ref=$d/TungstenRender.exr
  rw=$(oiiotool --info "$ref" | awk '{ print $3 }') rh=$(oiiotool --info "$ref" | awk '{ print $5 }' | tr -d ,)
  h=$(( (rh * width + rw / 2) / rw ))
  oiiotool "$ref" --resize "${width}x${h}" -o "$tmp/ref.exr"
  for mode in rgb truth; do
    "$bin" render "$d/scene-v4.pbrt" --mode "$mode" --width "$width" --height "$h" --spp "$spp" \
      --json -o "$tmp/$mode.exr" > "$tmp/$mode.json" 2> "$tmp/$mode.err"
    tris=$(jq .bvh.triangles "$tmp/$mode.json")
    secs=$(jq '.wall_s * 10 | round / 10' "$tmp/$mode.json")
    ign=$(grep -o ': [A-Z][A-Za-z]* "[a-z]*"[^:]*ignored' "$tmp/$mode.err" | sed 's/^: //; s/ ignored$//' |
          sort -u | paste -sd ';' - | sed 's/;/; /g')
    "$bin" compare "$tmp/ref.exr" "$tmp/$mode.exr" --json > "$tmp/cmp.json"
    ratio=$(awk -v a="$(luma "$tmp/ref.exr")" -v b="$(luma "$tmp/$mode.exr")" 'BEGIN { printf "%.3f", b / a }')
    printf '| %s | %s | %s | %s | %.2f | %.2f | %s | %s |\n' "$s" "$tris" "${ign:-none}" "$mode" \
      "$(jq .mean "$tmp/cmp.json")" "$(jq .p99 "$tmp/cmp.json")" "$ratio" "$secs"
  done
done
