#!/usr/bin/env bash
# ml against the 1 nm truth on the same paths, per bundled scene and
# threshold: ΔE00 (specmip compare defaults: 5x5 blur) of ref and ml against
# truth, ml's share of paths per level, and the render times of ml, ref and
# truth (--stats --json "render" wall time of one run each: a shared machine
# varies by several per cent, so compare ratios, not single runs, with care).
# usage: tools/levels_vs_truth.sh [binary] [size] [spp] [thresholds...]
#   defaults: build/specmip 96 64 1 2
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$here/build/specmip}
size=${2:-96}
spp=${3:-64}
shift $(($# < 3 ? $# : 3))
thresholds=("$@")
[ "$#" -gt 0 ] || thresholds=(1 2)
[ -x "$bin" ] || { echo "levels_vs_truth: no binary at $bin" >&2; exit 2; }
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$here/build/pocl-cache}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

render() { # scene mode out threshold -> prints the --stats JSON
    "$bin" render "$1" --mode "$2" --width "$size" --height "$size" --spp "$spp" --seed 1 \
        --threshold "$4" --quiet --stats --json -o "$3" 2>/dev/null
}
de() { # a b -> "mean p99 max"
    "$bin" compare "$1" "$2" --json | python3 -c '
import json, sys
d = json.load(sys.stdin)
print("%.2f / %.2f / %.2f" % (d["mean"], d["p99"], d["max"]))'
}

printf '| scene | T | ref vs truth mean / p99 / max | ml vs truth mean / p99 / max | ml paths per level (400/80/40/20/10 bins) | ml ÷ ref | ml ÷ truth |\n'
printf '|---|---|---|---|---|---|---|\n'
for scene in "$here"/scenes/*.scene; do
    name=$(basename "$scene" .scene)
    render "$scene" truth "$tmp/truth.exr" 2 > "$tmp/truth.json"
    render "$scene" ref "$tmp/ref.exr" 2 > "$tmp/ref.json"
    rde=$(de "$tmp/truth.exr" "$tmp/ref.exr")
    for t in "${thresholds[@]}"; do
        render "$scene" ml "$tmp/ml.exr" "$t" > "$tmp/ml.json"
        mde=$(de "$tmp/truth.exr" "$tmp/ml.exr")
        python3 - "$tmp" "$name" "$t" "$rde" "$mde" <<'PY'
import json, sys
tmp, name, t, rde, mde = sys.argv[1:]
js = {m: json.load(open(f"{tmp}/{m}.json")) for m in ("truth", "ref", "ml")}
ml = js["ml"]
paths = ml["paths"] or 1
share = {}
for lv in ml["levels"]:
    share[lv["level"]] = share.get(lv["level"], 0) + lv["paths"]
shares = " / ".join("%.1f%%" % (100.0 * share.get(l, 0) / paths) for l in range(5))
r = lambda m: js[m]["stages"]["render_s"]
print(f"| {name} | {t} | {rde} | {mde} | {shares} | {r('ml') / r('ref'):.2f} | {r('ml') / r('truth'):.2f} |")
PY
    done
done
