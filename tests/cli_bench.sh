#!/bin/bash
# specmip bench on one tiny scene: the CSV read back (header, rows, finite
# numbers, invariants), the charts (PNG files), RESULTS.md, an interrupted
# study keeping its finished rows, and exit 2 on bad options.
source "$(dirname "$0")/lib_cli.sh"
col() {  # col CSV NAME: the values of column NAME, one per line
    awk -F, -v n="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == n) c = i; next } { print $c }' "$1"
}

"$BIN" bench --scenes "$DATA/scenes/cornell.scene" --size 32x32 --spp 1,2 --truth-spp 4 \
    --modes ref,ml --thresholds 1,4 --repeat 2 --out "$T/out" --quiet 2> "$T/err.txt"
rc=$?
check "bench exits 0 (got $rc: $(tail -1 "$T/err.txt"))" test $rc -eq 0
csv=$T/out/bench.csv
check "CSV written" test -s "$csv"
check "no part file left" test ! -e "$csv.part"
for c in scene kind mode threshold spp wall_s kernel_s trace_s shade_s paths_per_s l0_paths l1_paths \
         l2_paths l3_paths l4_paths bias_ref_mean bias_ref_p99 bias_ref_max bias_truth_mean err_mean \
         noise_mean conv_floor_mean; do
    check "header has $c" grep -q "^\(.*,\)\?$c\(,.*\)\?$" <(head -1 "$csv")
done
# 2 spp x 2 modes (truth is rendered but has no row) + 2 thresholds of the sweep
check "row count 6" test "$(($(wc -l < "$csv") - 1))" -eq 6
check "every row has as many fields as the header" \
    awk -F, 'NR == 1 { n = NF } NF != n { exit 1 }' "$csv"
# from column 4 on everything is a finite number (no nan, inf or empty field)
check "numbers finite" awk -F, 'NR > 1 { for (i = 4; i <= NF; i++)
    if ($i !~ /^-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?$/) exit 1 }' "$csv"
check "modes and kinds" test "$(awk -F, 'NR > 1 { print $2 "/" $3 }' "$csv" | sort | uniq -c | awk '{ printf "%s%s", $1, $2 }')" = "2main/ml2main/ref2sweep/ml"
# every path is counted at exactly one level, and 32x32 pixels x spp paths ran
check "level counts add up to the paths" awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { if ($c["l0_paths"] + $c["l1_paths"] + $c["l2_paths"] + $c["l3_paths"] + $c["l4_paths"] != $c["paths"] ||
          $c["paths"] != 1024 * $c["spp"]) exit 1 }' "$csv"
# ref against itself: the same image, so exactly 0; ml differs from ref only by its levels
check "ref's bias against ref is 0" test "$(awk -F, '$3 == "ref"' "$csv" | wc -l)" -eq 2 -a \
    "$(paste -d, <(col "$csv" mode) <(col "$csv" bias_ref_max) | awk -F, '$1 == "ref" && $2 != 0' | wc -l)" -eq 0
# each main row's time ratio is its wall time over ref's at the same spp (wall_s
# has 6 decimals: ~1e-3 relative at these sub-millisecond times, both ways)
check "main rows: time_vs_ref is wall_s over ref's wall_s at that spp" awk -F, '
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["kind"] == "main" { row[NR] = $0; if ($c["mode"] == "ref") ref[$c["spp"]] = $c["wall_s"] }
    END { for (n in row) { split(row[n], f, ",")
            w = f[c["wall_s"]]; r = ref[f[c["spp"]]]; q = f[c["time_vs_ref"]]
            if (!(r > 0) || (q - w / r) ^ 2 > (q * (5e-7 / w + 5e-7 / r) + 5e-5) ^ 2) exit 1 }
          if (length(ref) != 2) exit 1 }' "$csv"
# ml off ref's level 1 differs from ref (its bias is not 0), and the sweep's
# thresholds reach the tables: threshold 4 puts paths on coarser levels than 1
check "ml off ref's level: bias against ref above 0" awk -F, '
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["mode"] == "ml" && $c["l1_paths"] < $c["paths"] { n++; if (!($c["bias_ref_mean"] > 0)) exit 1 }
    END { exit !(n >= 2) }' "$csv"
check "sweep: a higher threshold, coarser levels" awk -F, '
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["kind"] == "sweep" { m[$c["threshold"]] = $c["l1_paths"] + 2 * $c["l2_paths"] + 3 * $c["l3_paths"] + 4 * $c["l4_paths"] }
    END { exit !(m[4] > m[1]) }' "$csv"
check "the converged floor is the same in every row" test "$(col "$csv" conv_floor_mean | sort -u | wc -l)" -eq 1

for p in time_error bias threshold levels; do
    f=$T/out/$p.png
    check "$p.png written" test -s "$f"
    check "$p.png is a PNG" test "$(head -c 8 "$f" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a"
done
check "RESULTS.md has the scene's table" grep -q "^| ml |" "$T/out/RESULTS.md"
check "RESULTS.md states the command" grep -q "specmip bench --scenes" "$T/out/RESULTS.md"

# Ctrl-C: the render in flight is dropped, finished rows stay, under the final name
"$BIN" bench --scenes "$DATA/scenes/cornell.scene" --size 64x64 --spp 1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16 \
    --truth-spp 16 --modes ref --thresholds none --repeat 1 --out "$T/int" --no-charts --quiet 2> /dev/null &
pid=$!
for _ in $(seq 200); do  # until the first row is in (at most 20 s)
    [ "$(wc -l 2> /dev/null < "$T/int/bench.csv.part" || echo 0)" -ge 2 ] && break
    sleep 0.1
done
kill -INT $pid
wait $pid
rc=$?
check "interrupted: exit 130 (got $rc)" test $rc -eq 130
check "interrupted: finished rows kept in bench.csv" test "$(wc -l < "$T/int/bench.csv")" -ge 2
check "interrupted: fewer rows than the plan" test "$(wc -l < "$T/int/bench.csv")" -lt 17

expect_exit2() {  # expect_exit2 WHAT PATTERN ARGS...
    local what=$1 pattern=$2; shift 2
    "$BIN" bench --out "$T/bad" --quiet "$@" > /dev/null 2> "$T/err.txt"
    local rc=$?
    check "$what: exit 2 (got $rc)" test $rc -eq 2
    check "$what: message matches '$pattern'" grep -q -- "$pattern" "$T/err.txt"
}
expect_exit2 "unknown mode" "unknown mode 'rgbx'" --modes ref,rgbx
expect_exit2 "descending spp" "ascending" --spp 4,2
expect_exit2 "bad size" "WxH" --size 32
expect_exit2 "even blur" "odd" --blur 4
expect_exit2 "unknown option" "unknown option" --frobnicate
expect_exit2 "missing scene" "nonexistent.scene" --scenes "$T/nonexistent.scene" --size 8x8 --spp 1 \
    --truth-spp 1 --thresholds none

finish
