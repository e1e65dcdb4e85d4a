#!/usr/bin/env bash
# ml against the 1 nm truth on the same paths, per bundled scene and
# threshold: ΔE00 (specmip compare defaults: 5x5 blur) of ref and ml against
# truth, ml's share of paths per level, and ml's render time over ref's and
# truth's: the median of RUNS runs of each (--stats --json "render" wall
# time), the modes alternating run by run so that a shared machine's load
# drifts over all of them alike.
# usage: tools/levels_vs_truth.sh [binary] [size] [spp] [thresholds...]
#   defaults: build/specmip 96 64 1 2; RUNS=3 in the environment
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$here/build/specmip}
size=${2:-96}
spp=${3:-64}
shift $(($# < 3 ? $# : 3))
thresholds=("$@")
[ "$#" -gt 0 ] || thresholds=(1 2)
runs=${RUNS:-3}
[ -x "$bin" ] || { echo "levels_vs_truth: no binary at $bin" >&2; exit 2; }
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "levels_vs_truth: RUNS must be a positive integer" >&2; exit 2; }
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
    # same seed: every run renders the same image, so any run's image serves
    for r in $(seq "$runs"); do
        render "$scene" truth "$tmp/truth.exr" 2 > "$tmp/truth.$r.json"
        render "$scene" ref "$tmp/ref.exr" 2 > "$tmp/ref.$r.json"
        for t in "${thresholds[@]}"; do
            render "$scene" ml "$tmp/ml$t.exr" "$t" > "$tmp/ml$t.$r.json"
        done
    done
    rde=$(de "$tmp/truth.exr" "$tmp/ref.exr")
    for t in "${thresholds[@]}"; do
        mde=$(de "$tmp/truth.exr" "$tmp/ml$t.exr")
        python3 - "$tmp" "$name" "$t" "$rde" "$mde" "$runs" <<'PY'
import json, statistics, sys
tmp, name, t, rde, mde, runs = sys.argv[1:]
runs = range(1, int(runs) + 1)
js = {m: [json.load(open(f"{tmp}/{m}.{r}.json")) for r in runs] for m in ("truth", "ref", "ml" + t)}
ml = js["ml" + t][0]
paths = ml["paths"] or 1
share = {}
for lv in ml["levels"]:
    share[lv["level"]] = share.get(lv["level"], 0) + lv["paths"]
shares = " / ".join("%.1f%%" % (100.0 * share.get(l, 0) / paths) for l in range(5))
r = lambda m: statistics.median(j["stages"]["render_s"] for j in js[m])
print(f"| {name} | {t} | {rde} | {mde} | {shares} | {r('ml' + t) / r('ref'):.2f} | {r('ml' + t) / r('truth'):.2f} |")
PY
    done
done
