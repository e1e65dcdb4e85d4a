#!/bin/bash
# `specmip bench --rays`: on a generated mesh the replay kernel answers every
# recorded ray as the CPU reference does (Embree's agreement is
# cli_bench_rays_embree.sh); a saved ray file replays the same rays; bad ray
# files and misplaced options exit 2 naming the file and the problem.
# usage: bash tests/cli_bench_rays.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
python3 "$ROOT/tools/gen_meshes.py" --scale sphere 5000 "$T/s.ply" "$T/s.scene" > /dev/null ||
  { echo "FAIL: gen_meshes.py --scale"; exit 1; }
B=(bench --rays "$T/s.scene" --size 40x40 --repeat 1 --json)

# 1. kernel against reference, and the ray file written
"$BIN" "${B[@]}" --rays-stats --rays-save "$T/r.bin" > "$T/a.json" 2> "$T/err"
check "replay runs (exit 0)" test $? -eq 0
check "the rays are many" num "$(jnum "$T/a.json" '[.rays_closest, .rays_shadow] | min')" '>' 1000
check "kernel = reference on every closest-hit ray" num "$(jnum "$T/a.json" .reference.closest_differ)" == 0
check "kernel = reference on every shadow ray" num "$(jnum "$T/a.json" .reference.shadow_differ)" == 0
check "rays/s measured" num "$(jnum "$T/a.json" .specmip.closest_mrays_s)" '>' 0
check "nodes per ray counted" num "$(jnum "$T/a.json" .specmip.nodes_closest)" '>=' 1
check "ray file written, no .part left" test -s "$T/r.bin" -a ! -e "$T/r.bin.part"

# 2. the file replays the same rays
"$BIN" "${B[@]}" --rays-load "$T/r.bin" > "$T/b.json" 2> "$T/err"
check "replay of the file (exit 0)" test $? -eq 0
check "same closest-hit ray count from the file" \
  num "$(jnum "$T/a.json" .rays_closest)" == "$(jnum "$T/b.json" .rays_closest)"
check "same shadow ray count from the file" \
  num "$(jnum "$T/a.json" .rays_shadow)" == "$(jnum "$T/b.json" .rays_shadow)"
check "file: kernel = reference" \
  num "$(jnum "$T/b.json" '.reference.closest_differ + .reference.shadow_differ')" == 0

# 2b. the packet variant (work-groups of 3: the last group has lanes beyond the
#     rays) answers every ray as the reference, on the file's order and sorted;
#     its lanes visit the union of the group's nodes, so more nodes per ray than
#     one ray per work-item (which says the variant ran); the sort keeps the rays
#     and changes their order
"$BIN" "${B[@]}" --rays-load "$T/r.bin" --rays-packet --rays-group 3 --rays-stats > "$T/p.json" 2> "$T/err"
check "packet replay runs (exit 0: $(head -1 "$T/err"))" test $? -eq 0
check "packets: kernel = reference on every ray" \
  num "$(jnum "$T/p.json" '.reference.closest_differ + .reference.shadow_differ')" == 0
check "packets: more nodes per closest-hit ray than one ray per work-item" \
  num "$(jnum "$T/p.json" .specmip.nodes_closest)" '>' "$(jnum "$T/a.json" .specmip.nodes_closest)"
"$BIN" "${B[@]}" --rays-load "$T/r.bin" --rays-sort --rays-packet --rays-group 8 \
  --rays-save "$T/sorted.bin" > "$T/q.json" 2> "$T/err"
check "sorted packet replay runs (exit 0: $(head -1 "$T/err"))" test $? -eq 0
check "sorted packets: kernel = reference on every ray" \
  num "$(jnum "$T/q.json" '.reference.closest_differ + .reference.shadow_differ')" == 0
check "sorted: as many rays" num "$(jnum "$T/q.json" '.rays_closest + .rays_shadow')" == \
  "$(jnum "$T/a.json" '.rays_closest + .rays_shadow')"
check "sorted: same size, other order" \
  sh -c "test \$(wc -c < '$T/sorted.bin') -eq \$(wc -c < '$T/r.bin') && ! cmp -s '$T/sorted.bin' '$T/r.bin'"

# 3. bad input: exit 2, the file and the problem named
bad_file() {  # bad_file WHAT PATTERN ARGS...
  local what=$1 pat=$2; shift 2
  "$BIN" bench --repeat 1 "$@" > "$T/out" 2> "$T/err"
  local rc=$?
  check "$what: exit 2 (got $rc)" test $rc -eq 2
  check "$what: says '$pat'" grep -q -- "$pat" "$T/err"
}
head -c 1000 "$T/r.bin" > "$T/short.bin"
bad_file "truncated file" "short.bin: truncated" --rays "$T/s.scene" --rays-load "$T/short.bin"
bad_file "other scene's file" "r.bin: recorded on other geometry" --rays default --rays-load "$T/r.bin"
printf 'not rays' > "$T/junk.bin"
bad_file "not a ray file" "junk.bin: not a ray file" --rays "$T/s.scene" --rays-load "$T/junk.bin"
bad_file "missing file" "nothere.bin" --rays "$T/s.scene" --rays-load "$T/nothere.bin"
bad_file "unwritable ray file" "nodir/r.bin" --rays "$T/s.scene" --size 8x8 --rays-save "$T/nodir/r.bin"
bad_file "--embree without --rays" "go with --rays" --embree
bad_file "bad --rays-spp" "rays-spp" --rays default --rays-spp 0
bad_file "packets of more than 64" "at most 64" --rays default --size 8x8 --rays-packet --rays-group 65

# 4. bench/scale.sh at a tiny size: a row per case with every column, the
#    replay equal to the reference, and the chart
SPECMIP=$BIN SCALE_SHAPES="sphere soup" SCALE_SIZES=200 SCALE_SCENES=0 SCALE_RENDER="16x16 1" \
  SCALE_RAYS="24x24 1" SCALE_REPEAT=1 SCALE_EMBREE=0 bash "$ROOT/bench/scale.sh" "$T/scale" \
  > "$T/scale.log" 2>&1
check "scale.sh runs (exit 0)" test $? -eq 0
check "scale.sh: a row per case" test "$(grep -c '^sphere-200,\|^soup-200,' "$T/scale/scale.csv")" -eq 2
check "scale.sh: every row has the header's columns" awk -F, 'NR == 1 { n = NF } NF != n { exit 1 }' \
  "$T/scale/scale.csv"
check "scale.sh: triangles, rays/s and memory filled in" awk -F, \
  'NR > 1 && !($2 >= 190 && $12 > 0 && $13 > 0 && $9 > 0) { exit 1 }' "$T/scale/scale.csv"
check "scale.sh: replay = reference" awk -F, 'NR > 1 && $20 != 0 { exit 1 }' "$T/scale/scale.csv"
check "scale.sh: chart written" test -s "$T/scale/scale.png"
SPECMIP=$BIN SCALE_SIZES=abc bash "$ROOT/bench/scale.sh" "$T/scale2" > /dev/null 2> "$T/err"
check "scale.sh: a bad size exits 2" test $? -eq 2
check "scale.sh: says why" grep -q "SCALE_SIZES: 'abc'" "$T/err"
finish
