# No timed render compiles kernels: on an empty PoCL cache a render's build
# stage launches every kernel in each shape its passes use (cl_render_program.c,
# spm_clr_warm_up), so render --json's compiled_during_timing is false and
# the bench's rows are 0. The render is 200x200 at 3 spp: passes of 2 spp
# (80000 work-items, over PoCL's 65535 grid limit) and a last one of 1 spp
# (40000, under it), so it needs both of PoCL's grid classes. The cache is
# this test's own: other tests compiling into a shared one would look like
# this render compiling.
source "$(dirname "$0")/lib_cli.sh"
export POCL_CACHE_DIR=$T/pocl
mkdir -p "$POCL_CACHE_DIR"
"$BIN" render "$DATA/scenes/cornell.scene" --width 200 --height 200 --spp 3 --json --quiet \
    -o "$T/a.exr" > "$T/r.json" 2> "$T/err"
rc=$?
check "render exits 0 (got $rc: $(tail -1 "$T/err"))" test $rc -eq 0
check "render: passes of 2 and 1 spp (3 in all)" test "$(jq '.passes' "$T/r.json")" = 2
check "render: the PoCL cache was filled (the watch has something to watch)" \
    test "$(find "$POCL_CACHE_DIR" -name '*.so' | wc -l)" -gt 0
check "render: compiled_during_timing is a boolean" \
    test "$(jq -r '.compiled_during_timing | type' "$T/r.json")" = boolean
check "render: no compile during the render stage on an empty cache" \
    test "$(jq -r '.compiled_during_timing' "$T/r.json")" = false
check "render: no WARNING" test "$(grep -c WARNING "$T/err")" -eq 0

# The bench: its rows' timed renders (64x64 at 16 spp: one pass of 65536 paths,
# over the limit, after the bench's own warm-up pass of 1 spp, under it)
rm -rf "$POCL_CACHE_DIR" && mkdir -p "$POCL_CACHE_DIR"
"$BIN" bench --scenes "$DATA/scenes/cornell.scene" --size 64x64 --spp 4,16 --truth-spp 16 --modes ref \
    --budgets none --thresholds none --repeat 1 --out "$T/b" --no-charts --quiet 2> "$T/berr"
rc=$?
check "bench exits 0 (got $rc: $(tail -1 "$T/berr"))" test $rc -eq 0
check "bench: every row's compiled_during_timing is 0" awk -F, '
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; if (!("compiled_during_timing" in c)) exit 1; next }
    { n++; if ($c["compiled_during_timing"] != "0") bad++ } END { exit !(n == 2 && !bad) }' "$T/b/bench.csv"
check "bench: no WARNING" test "$(grep -c WARNING "$T/berr")" -eq 0
finish
