#!/bin/bash
# Charts (gnuplot) and RESULTS.md from a `specmip bench` directory:
#   bench/report/bench_report.sh DIR [OUTDIR]
# reads DIR/bench.csv, DIR/bench_meta.txt and, if present, DIR/ops.csv and
# DIR/ops_meta.txt (from `specmip bench --ops --out DIR`); writes time_error.png (error
# against time at equal time), bias.png, threshold.png, levels.png and RESULTS.md into
# OUTDIR (default DIR).
# For the README: bench/report/bench_report.sh bench-out docs
set -eu
dir=${1:?usage: bench_report.sh DIR [OUTDIR]}
out=${2:-$dir}
here=$(cd "$(dirname "$0")" && pwd)
csv=$dir/bench.csv
[ -s "$csv" ] || { echo "bench_report.sh: no $csv" >&2; exit 2; }
command -v gnuplot > /dev/null || { echo "bench_report.sh: gnuplot is not installed" >&2; exit 1; }
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

sel="awk -F, -f $here/bench_select.awk"
scenes=$($sel -v kind=main -v cols=scene "$csv" | awk '!s[$0]++' | tr '\n' ' ')
modes=$($sel -v kind=main -v cols=mode "$csv" | awk '!s[$0]++' | tr '\n' ' ')
nsc=$(echo $scenes | wc -w)
sweep=$($sel -v kind=sweep -v cols=scene "$csv" | head -1 | wc -l)
equal=$($sel -v kind=equal -v cols=scene "$csv" | head -1 | wc -l)
# the levelled modes among them, from the bench's copy of `specmip modes`
[ -s "$dir/modes.tsv" ] || { echo "bench_report.sh: no $dir/modes.tsv (written by specmip bench)" >&2; exit 2; }
lvmodes=$(for m in $(awk -F'\t' '$2 == "levelled" { print $1 }' "$dir/modes.tsv"); do
    case " $modes " in *" $m "*) printf '%s ' $m;; esac; done)

for w in bias_ref bias_truth; do awk -v what=$w -f "$here/bench_tables.awk" "$csv" > "$tmp/$w.dat"; done
for m in $lvmodes; do awk -v what=levels -v mode=$m -f "$here/bench_tables.awk" "$csv" > "$tmp/levels_$m.dat"; done

gnuplot -e "csv='$csv'; out='$out'; sel='$sel'; scenes='$scenes'; modes='$modes'; nsc=$nsc; \
            dat='$tmp'; sweep=$sweep; equal=$equal; lvmodes='$lvmodes'" "$here/bench_plots.gp"

# Fewer colours (if ImageMagick is there): the charts are committed to docs/.
if command -v convert > /dev/null; then
    for f in time_error bias threshold levels; do
        [ -s "$out/$f.png" ] && convert "$out/$f.png" -colors 64 "PNG8:$tmp/$f.png" && mv "$tmp/$f.png" "$out/$f.png"
    done
fi

ops="" opsmeta=""
[ -s "$dir/ops.csv" ] && ops=$dir/ops.csv opsmeta=$dir/ops_meta.txt
awk -v meta="$dir/bench_meta.txt" -v ops="$ops" -v opsmeta="$opsmeta" -f "$here/bench_results.awk" "$csv" > "$tmp/RESULTS.md"
mv "$tmp/RESULTS.md" "$out/RESULTS.md"
echo "bench_report.sh: charts and RESULTS.md in $out" >&2
