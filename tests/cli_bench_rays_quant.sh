#!/bin/bash
# `specmip bench --rays --rays-quant`: the quantised tree (64-byte nodes, 8-bit
# child boxes rounded outward) answers every recorded ray as the CPU reference
# does, on the same ray files as the wide tree (so as the wide kernel too), on
# a smooth sphere and on a random soup (overlapping slivers: many grazing
# rays); its tree buffer is smaller, which says the variant ran; with the
# packet variant it is refused (exit 2).
# usage: bash tests/cli_bench_rays_quant.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
for shape in sphere soup; do
  python3 "$ROOT/tools/gen_meshes.py" --scale $shape 4000 "$T/$shape.ply" "$T/$shape.scene" > /dev/null ||
    { echo "FAIL: gen_meshes.py --scale $shape"; exit 1; }
  B=(bench --rays "$T/$shape.scene" --size 40x40 --repeat 1 --json --rays-stats)
  "$BIN" "${B[@]}" --rays-save "$T/$shape.rays" > "$T/w.json" 2> "$T/err"
  check "$shape: wide replay runs (exit 0: $(head -1 "$T/err"))" test $? -eq 0
  "$BIN" "${B[@]}" --rays-load "$T/$shape.rays" --rays-quant > "$T/q.json" 2> "$T/err"
  check "$shape: quantised replay runs (exit 0: $(head -1 "$T/err"))" test $? -eq 0
  check "$shape: the rays are many" num "$(jnum "$T/q.json" '[.rays_closest, .rays_shadow] | min')" '>' 1000
  check "$shape: it says the quantised nodes ran" grep -q '"what": "specmip kernels/rays.cl (quantised nodes)' "$T/q.json"
  check "$shape: quantised = reference on every closest-hit ray" \
    num "$(jnum "$T/q.json" .reference.closest_differ)" == 0
  check "$shape: quantised = reference on every shadow ray" \
    num "$(jnum "$T/q.json" .reference.shadow_differ)" == 0
  check "$shape: wide = reference on every ray" \
    num "$(jnum "$T/w.json" '.reference.closest_differ + .reference.shadow_differ')" == 0
  check "$shape: nodes per ray counted" num "$(jnum "$T/q.json" .specmip.nodes_closest)" '>=' 1
  check "$shape: the quantised tree is smaller" \
    num "$(jnum "$T/q.json" .tree_bytes)" '<' "$(jnum "$T/w.json" .tree_bytes)"
done
"$BIN" bench --rays default --size 8x8 --repeat 1 --rays-quant --rays-packet > "$T/out" 2> "$T/err"
rc=$?
check "--rays-quant with --rays-packet: exit 2 (got $rc)" test $rc -eq 2
check "--rays-quant with --rays-packet: says so" grep -q "one variant at a time" "$T/err"
finish
