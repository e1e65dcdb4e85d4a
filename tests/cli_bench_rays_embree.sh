#!/bin/bash
# `specmip bench --rays --embree`: Embree 3 answers the recorded rays of a
# generated mesh as the kernel does on at least 99.9 % of them. Embree is
# optional (tools/setup.sh --bench installs it): a build without it says so
# when asked, and this test is then skipped (exit 77), the one skip the
# README's fresh machine shows.
# usage: bash tests/cli_bench_rays_embree.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
python3 "$ROOT/tools/gen_meshes.py" --scale sphere 5000 "$T/s.ply" "$T/s.scene" > /dev/null ||
  { echo "FAIL: gen_meshes.py --scale"; exit 1; }
"$BIN" bench --rays "$T/s.scene" --size 40x40 --repeat 1 --json --embree > "$T/e.json" 2> "$T/err"
rc=$?
if [ $rc -ne 0 ] && grep -q "built without Embree" "$T/err"; then
  skip "this build has no Embree (tools/setup.sh --bench, then build again)"
fi
check "replay with Embree: exit 0 (got $rc: $(tail -1 "$T/err"))" test $rc -eq 0
n=$(jnum "$T/e.json" '.rays_closest + .rays_shadow')
d=$(jnum "$T/e.json" '.embree.closest_differ + .embree.shadow_differ')
check "many rays ($n)" num "$n" '>' 2000
check "Embree agrees on >= 99.9 % of rays ($d of $n differ)" \
  num "$d" '<=' "$(is_num "$n" && awk -v n="$n" 'BEGIN { print n / 1000 }')"
check "Embree's rays/s measured" num "$(jnum "$T/e.json" .embree.closest_mrays_s)" '>' 0
finish
