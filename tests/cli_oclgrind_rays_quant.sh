#!/bin/bash
# The quantised tree's ray replay (`bench --rays --rays-quant`,
# kernels/traverse_quant.clh) under Oclgrind: every access of the 64-byte
# nodes and the leaf planes behind them in bounds (nothing in Oclgrind's log)
# and every answer the CPU reference's. Oclgrind's own ability to see a read
# past a buffer is cli_oclgrind.sh's check.
# usage: bash tests/cli_oclgrind_rays_quant.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
python3 "$ROOT/tools/gen_meshes.py" --scale soup 3000 "$T/s.ply" "$T/s.scene" > /dev/null ||
  { echo "FAIL: gen_meshes.py --scale soup"; exit 1; }
oclgrind --check-api --data-races --log "$T/og.log" "$BIN" bench --rays "$T/s.scene" --size 8x8 \
  --repeat 1 --rays-quant --rays-stats --json > "$T/q.json" 2> "$T/err"
rc=$?
check "exit 0 under Oclgrind (got $rc: $(head -1 "$T/err"))" test $rc -eq 0
check "Oclgrind ran it" grep -q '"what": "specmip kernels/rays.cl (quantised nodes) on Oclgrind' "$T/q.json"
check "Oclgrind's log is empty" test ! -s "$T/og.log"
[ -s "$T/og.log" ] && head -20 "$T/og.log" >&2
check "the rays are there" num "$(jnum "$T/q.json" '[.rays_closest, .rays_shadow] | min')" '>' 50
check "= reference on every ray" \
  num "$(jnum "$T/q.json" '.reference.closest_differ + .reference.shadow_differ')" == 0
finish
