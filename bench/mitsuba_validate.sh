#!/usr/bin/env bash
# Mitsuba 3 scenes rendered from their own files by specmip and by Mitsuba 3
# (llvm_ad_spectral, the peer) and compared (docs/VALIDATION_MITSUBA.md): mean
# and p99 CIEDE2000 (specmip compare, 5 x 5 box blur) of specmip seed 1
# against Mitsuba, beside the two-seed floor (specmip seed 1 against seed 2
# at the same spp), the ratio of the two, the ratio of mean luminances and
# both render times. Mitsuba renders with -D max_depth=-1 where the file
# names $max_depth (specmip's paths end by Russian roulette: every bounce).
# Then each test scene of mitsuba-data (tests/scenes/*/*.xml, which have
# reference EXRs per variant) with what `render --strict` says first: the
# element that keeps it from being compared.
# Usage: bench/mitsuba_validate.sh MITSUBA_DATA [SPECMIP] [SPP] [MITSUBA_SPP]
#   MITSUBA_DATA: a checkout of mitsuba-renderer/mitsuba-data
#   MITSUBA: the mitsuba command (default: mitsuba on PATH); Mitsuba 3 from
#   PyPI in a venv, with DRJIT_LIBLLVM_PATH set to libLLVM.so (Debian: libllvm19).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
src=${1:?usage: bench/mitsuba_validate.sh MITSUBA_DATA [SPECMIP] [SPP] [MITSUBA_SPP]}
src=$(cd "$src" && pwd)
bin=${2:-$here/build/specmip}
spp=${3:-256}
mspp=${4:-1024}
mitsuba=${MITSUBA:-mitsuba}
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$here/build/pocl-cache}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
luma() { oiiotool --stats "$1" 2>/dev/null | awk '/Stats Avg/ { print 0.2126 * $3 + 0.7152 * $4 + 0.0722 * $5 }'; }
secs() { local t0=$(date +%s.%N); "$@"; awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }' > "$tmp/secs"; }
# scene file, its display name
scenes=("$src/scenes/cbox/cbox-spectral.xml:cbox-spectral"
        "$here/tests/data/mitsuba/box/box.xml:tests/data/mitsuba/box")
echo "# specmip $spp spp, Mitsuba 3 llvm_ad_spectral $mspp spp; CPU: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores (shared)"
echo "| scene | size | mean dE00 vs Mitsuba | p99 | floor mean (2 seeds) | p99 | mean / floor | luminance ratio | specmip (s) | Mitsuba (s) |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"
for entry in "${scenes[@]}"; do
  file=${entry%%:*} name=${entry#*:}
  (cd "$(dirname "$file")"
   defs=(-D spp="$mspp")
   grep -rqF --include='*.xml' '$max_depth' . && defs+=(-D max_depth=-1) # its includes too
   secs "$mitsuba" -m llvm_ad_spectral "${defs[@]}" -o "$tmp/mi.exr" "$file" > "$tmp/mi.log" 2>&1)
  mt=$(cat "$tmp/secs")
  for seed in 1 2; do
    "$bin" render "$file" --spp "$spp" --seed "$seed" --json -o "$tmp/s$seed.exr" \
      > "$tmp/s$seed.json" 2> "$tmp/s$seed.err"
  done
  st=$(jq '.wall_s * 10 | round / 10' "$tmp/s1.json")
  "$bin" compare "$tmp/mi.exr" "$tmp/s1.exr" --json > "$tmp/cmp.json"
  "$bin" compare "$tmp/s2.exr" "$tmp/s1.exr" --json > "$tmp/floor.json"
  size=$(oiiotool --info "$tmp/s1.exr" | awk '{ print $3 "x" $5 }' | tr -d ,)
  ratio=$(awk -v a="$(luma "$tmp/mi.exr")" -v b="$(luma "$tmp/s1.exr")" 'BEGIN { printf "%.3f", b / a }')
  printf '| %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %s | %s | %s |\n' "$name" "$size" \
    "$(jq .mean "$tmp/cmp.json")" "$(jq .p99 "$tmp/cmp.json")" "$(jq .mean "$tmp/floor.json")" \
    "$(jq .p99 "$tmp/floor.json")" "$(jq -n "$(jq .mean "$tmp/cmp.json") / $(jq .mean "$tmp/floor.json")")" \
    "$ratio" "$st" "$mt"
done
echo
echo "| mitsuba-data test scene | render --strict says first |"
echo "|---|---|"
for f in "$src"/tests/scenes/*/*.xml; do
  msg=$("$bin" render "$f" --strict --spp 1 --width 8 --height 8 --allow-path "$src/common" \
        -o "$tmp/x.exr" 2>&1 | grep -v '^specmip: ' | tail -1 | sed "s|$src/||g; s|^specmip render: ||; s/ (--strict makes this an error)//; s/|/\\\\|/g" || true)
  printf '| %s | %s |\n' "${f#$src/}" "${msg:-renders without a warning}"
done
