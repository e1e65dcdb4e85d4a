#!/bin/bash
# Regenerates the results README.md and docs/ carry, in one command:
#   bench/report/update_results.sh [SPECMIP] [-- extra specmip bench options]
# runs the default study (`specmip bench`: every bundled scene, every mode, equal
# time included) and the operator benchmark into bench-out/, then writes
# docs/RESULTS.md and the charts in docs/ (bench_report.sh) and README's headline
# table from it, between its results markers (readme_results.sh). Nothing is
# written to docs/ or README.md unless both runs finish.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${1:-$root/build/specmip}
[ $# -gt 0 ] && shift
[ "${1:-}" = "--" ] && shift
[ -x "$bin" ] || { echo "update_results.sh: no binary at $bin" >&2; exit 2; }
cd "$root"
out=bench-out
export POCL_CACHE_DIR=${POCL_CACHE_DIR:-$root/build/pocl-cache}
start=$(date +%s)
"$bin" bench --out "$out" --progress --no-charts "$@"
"$bin" bench --ops --out "$out"
bash bench/report/bench_report.sh "$out" docs
bash bench/report/readme_results.sh docs/RESULTS.md README.md
echo "update_results.sh: docs/RESULTS.md, the charts in docs/ and README.md regenerated in" \
     "$(( ($(date +%s) - start) / 60 )) min $(( ($(date +%s) - start) % 60 )) s" >&2
