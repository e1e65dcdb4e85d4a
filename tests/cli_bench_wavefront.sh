#!/bin/bash
# `specmip bench --rays SCENE --rays-wavefront N`: a wavefront of bounces,
# each traced in path order and sorted by octant and origin. The sort only
# permutes, so every sorted ray's answer equals the same ray's in path order,
# and the path order's equal the CPU reference's; the sort must move rays (a
# sort that did nothing would pass the first check); paths end at misses and
# emitters, so later bounces have fewer rays; misplaced options exit 2.
# usage: bash tests/cli_bench_wavefront.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
python3 "$ROOT/tools/gen_meshes.py" --scale sphere 2000 "$T/s.ply" "$T/s.scene" > /dev/null ||
  { echo "FAIL: gen_meshes.py --scale"; exit 1; }

for scene in default "$T/s.scene"; do
  name=$(basename "$scene")
  "$BIN" bench --rays "$scene" --size 24x20 --rays-wavefront 3 --repeat 1 --json \
    > "$T/w.json" 2> "$T/err"
  check "$name: runs (exit 0: $(head -1 "$T/err"))" test $? -eq 0
  check "$name: three bounces" num "$(jnum "$T/w.json" '.depths | length')" == 3
  check "$name: a camera ray per pixel" num "$(jnum "$T/w.json" '.depths[0].closest.rays')" == 480
  check "$name: shadow rays at every bounce" \
    num "$(jnum "$T/w.json" '[.depths[].shadow.rays] | min')" '>' 50
  check "$name: bounce rays at every depth" \
    num "$(jnum "$T/w.json" '[.depths[].closest.rays] | min')" '>' 50
  check "$name: sorted = path order on every ray" \
    num "$(jnum "$T/w.json" '[.depths[] | .closest.differ_sorted + .shadow.differ_sorted] | add')" == 0
  check "$name: path order = reference on every ray" \
    num "$(jnum "$T/w.json" '[.depths[] | .closest.differ_reference + .shadow.differ_reference] | add')" == 0
  check "$name: the sort moves most rays of every kind" \
    num "$(jnum "$T/w.json" '[.depths[] | .closest, .shadow | .moved / .rays] | min')" '>' 0.5
  check "$name: both orders timed" \
    num "$(jnum "$T/w.json" '[.depths[] | .closest, .shadow | .path_mrays_s, .sorted_mrays_s] | min')" '>' 0
done
check "default: paths end (fewer rays at bounce 3 than 1)" \
  num "$(jnum "$T/w.json" '.depths[2].closest.rays')" '<' 480

bad() {  # bad WHAT PATTERN ARGS...
  local what=$1 pat=$2; shift 2
  "$BIN" bench --repeat 1 --size 8x8 "$@" > "$T/out" 2> "$T/err"
  local rc=$?
  check "$what: exit 2 (got $rc)" test $rc -eq 2
  check "$what: says '$pat'" grep -q -- "$pat" "$T/err"
}
bad "--rays-wavefront 0" "rays-wavefront" --rays default --rays-wavefront 0
bad "--rays-wavefront 17" "rays-wavefront" --rays default --rays-wavefront 17
bad "with --rays-sort" "do not apply" --rays default --rays-wavefront 2 --rays-sort
bad "with --rays-load" "do not apply" --rays default --rays-wavefront 2 --rays-load "$T/x.bin"
finish
