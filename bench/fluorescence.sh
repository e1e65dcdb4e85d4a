#!/usr/bin/env bash
# The fluorescence cost ladder (docs/METHODS.md "Fluorescence"): on a
# fluorescent scene, the shade stage at every level (ml with every colour
# allowed down to level L: --threshold 1e6 --coarsest-level L puts every
# path at L), then every mode that renders fluorescence as it runs, side by
# side: shade and trace seconds, whole render seconds and paths/s, the best
# of ROUNDS runs taken in turns (the trace stage, the same work in every mode,
# bounds what a cheaper shade stage can buy); and ml's and mlc's dE00 against truth of the same
# paths (same seed and spp: the representation's error, no noise).
# Usage: bench/fluorescence.sh [SPECMIP] [SCENE] [WxH] [SPP] [ROUNDS]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$here/build/specmip}
scene=${2:-$here/scenes/fluorescent.scene}
size=${3:-128x128}
spp=${4:-16}
rounds=${5:-3}
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$here/build/pocl-cache}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
w=${size%x*} h=${size#*x}
runs=("L0:--mode ml --threshold 1e6 --coarsest-level 0" "L1:--mode ml --threshold 1e6 --coarsest-level 1"
      "L2:--mode ml --threshold 1e6 --coarsest-level 2" "L3:--mode ml --threshold 1e6 --coarsest-level 3"
      "L4:--mode ml --threshold 1e6 --coarsest-level 4"
      "truth:--mode truth" "ref:--mode ref" "ml:--mode ml" "mlc:--mode mlc" "rgb:--mode rgb")
echo "# $(basename "$scene") ${w}x${h}, $spp spp, best of $rounds; CPU: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
for r in $(seq "$rounds"); do
  for run in "${runs[@]}"; do
    name=${run%%:*}
    # shellcheck disable=SC2086
    "$bin" render "$scene" ${run#*:} --width "$w" --height "$h" --spp "$spp" --seed 1 --quiet \
      --json -o "$tmp/$name.exr" > "$tmp/$name.$r.json"
  done
done
printf '%-6s %10s %10s %10s %12s %10s %8s\n' run shade_s trace_s render_s paths/s shade/L3 levels
l3=$(for r in $(seq "$rounds"); do jq .shade_s "$tmp/L3.$r.json"; done | sort -g | head -1)
for run in "${runs[@]}"; do
  name=${run%%:*}
  best=$(for r in $(seq "$rounds"); do jq -r '"\(.shade_s) \(.trace_s) \(.wall_s) \(.paths_per_s)"' "$tmp/$name.$r.json"; done | sort -g | head -1)
  read -r s trace wall pps <<< "$best"
  lv=$(jq -r '[.levels[]?.paths] | map(tostring) | join("/")' "$tmp/$name.1.json")
  printf '%-6s %10.4f %10.4f %10.4f %12.0f %10.1f %8s\n' "$name" "$s" "$trace" "$wall" "$pps" \
    "$(awk -v a="$s" -v b="$l3" 'BEGIN { print a / b }')" "${lv:--}"
done
for m in ml mlc rgb ref; do
  echo "$m against truth (same paths):"
  "$bin" compare "$tmp/truth.exr" "$tmp/$m.exr" | grep -E -m2 "mean|^dE00"
done
