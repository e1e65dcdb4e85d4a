#!/usr/bin/env bash
# Pixel-identity check for refactoring: renders every bundled scene (and the
# built-in one) in every mode on both backends at a small size and prints one
# line per image: scene, mode, backend and the SHA-1 of its pixel data (OIIO's
# computePixelHashSHA1 over the float channels; EXR headers carry times and
# versions, so the file itself is not hashed). Two trees whose outputs are
# identical render identical pixels.
# Usage: tools/render_hashes.sh [SPECMIP_BINARY]   (default build/specmip)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$here/build/specmip}
command -v oiiotool >/dev/null || { echo "render_hashes: needs oiiotool (openimageio-tools)" >&2; exit 2; }
[ -x "$bin" ] || { echo "render_hashes: no binary at $bin" >&2; exit 2; }
modes=$("$bin" modes | cut -f1)
[ -n "$modes" ] || { echo "render_hashes: '$bin modes' listed no mode" >&2; exit 2; }
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$here/build/pocl-cache}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scenes=(default "$here"/scenes/*.scene)
for scene in "${scenes[@]}"; do
  arg=()
  [ "$scene" = default ] || arg=("$scene")
  for mode in $modes; do
    for backend in opencl cpu; do
      out=$tmp/img.exr
      rc=0
      "$bin" render "${arg[@]}" --mode "$mode" --backend "$backend" --width 24 --height 16 \
        --spp 4 --seed 7 --quiet -o "$out" >/dev/null 2>"$tmp/err" || rc=$?
      if [ "$rc" -eq 0 ]; then
        hash=$(oiiotool --hash "$out" | sed -n 's/.*SHA-1: *//p')
      elif [ "$rc" -eq 2 ]; then  # a mode that refuses the scene (a usage error): say so
        hash="refused"
      else
        cat "$tmp/err" >&2
        exit "$rc"
      fi
      printf '%-20s %-6s %-7s %s\n' "$(basename "$scene" .scene)" "$mode" "$backend" "$hash"
      rm -f "$out"
    done
  done
done
