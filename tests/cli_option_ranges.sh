#!/bin/bash
# The one option table (host/cli/cli_args.c spm_options): render, bench and
# spectrum are fed the same values just inside and just outside each range
# their help documents (the help is printed from the table); inside is
# accepted, outside exits 2 naming the option. An option render and bench
# both take documents one range in both. bench takes --device as render does:
# a list or 'all'.
# usage: bash tests/cli_option_ranges.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
cd "$T"
mkdir -p ops
# each command at its cheapest: a 4x4 CPU render, the operator benchmark at
# one item, a spectrum
run() {
  case $1 in
    render) "$BIN" render --backend cpu --width 4 --height 4 --spp 1 --quiet -o r.exr "${@:2}" ;;
    bench) "$BIN" bench --ops --ops-items 1 --ops-iters 1 --out ops "${@:2}" ;;
    spectrum) "$BIN" spectrum "$DATA/spectra/illuminant_F11.csv" --emission "${@:2}" ;;
  esac
}
expect() {  # expect CMD OPTION VALUE ok|refused
  run "$1" "$2" "$3" > out.txt 2> err.txt; local rc=$?
  if [ "$4" = ok ]; then
    [ $rc -eq 0 ] && ok || bad "$1 $2 $3: exit $rc, want 0: $(head -c 300 err.txt)"
  else
    [ $rc -eq 2 ] && grep -q -- "$2" err.txt && ok ||
      bad "$1 $2 $3: exit $rc, want 2 and a message naming $2: $(head -c 300 err.txt)"
  fi
}
for cmd in render bench; do
  expect $cmd --seed 0 ok
  expect $cmd --seed 4294967295 ok
  expect $cmd --seed -1 refused
  expect $cmd --seed 4294967296 refused
done
for cmd in render bench spectrum; do
  expect $cmd --threshold 0 ok
  expect $cmd --threshold 1000000 ok
  expect $cmd --threshold -0.001 refused
  expect $cmd --threshold 1000001 refused
done

# Every documented range, at the parser: the command is stopped right after
# the options by an argument too many (render: a second scene, bench: a bare
# word, spectrum: a second FILE), so an accepted value, however large, costs
# nothing, and the error then names the extra argument, not the option.
ranges() {  # ranges CMD: "OPTION VALUE-NAME LO HI" per option whose help says "LO to HI"
  "$BIN" "$1" --help | awk '
    /^  -/ { opt = ""; val = "";
             for (i = 1; i <= NF; i++) if ($i ~ /^--/) { opt = $i; sub(/,$/, "", opt); val = $(i + 1); break }
             done = 0 }
    opt != "" && !done && match($0, /[0-9.e+-]+ to [0-9.e+-]+/) {
        split(substr($0, RSTART, RLENGTH), r, " to "); print opt, val, r[1], r[2]; done = 1 }'
}
extra() {
  case $1 in
    render) echo "x1.scene x2.scene" ;;
    bench) echo "stray" ;;
    spectrum) echo "x1.csv x2.csv" ;;
  esac
}
at_parser() {  # at_parser CMD OPTION VALUE-NAME VALUE accepted|refused
  local v=$4
  [ "$3" = WxH ] && v=${4}x$4
  "$BIN" "$1" "$2" "$v" $(extra "$1") > out.txt 2> err.txt; local rc=$?
  if [ "$5" = accepted ]; then
    [ $rc -eq 2 ] && ! grep -q -- "$2" err.txt && grep -q "x2\|stray" err.txt && ok ||
      bad "$1 $2 $v: want it accepted (the extra argument refused): exit $rc: $(head -c 300 err.txt)"
  else
    [ $rc -eq 2 ] && grep -q -- "$2" err.txt && ok ||
      bad "$1 $2 $v: want exit 2 naming $2: exit $rc: $(head -c 300 err.txt)"
  fi
}
for cmd in render bench spectrum; do
  ranges $cmd > ranges_$cmd.txt
  check "$cmd --help documents ranges" test "$(wc -l < ranges_$cmd.txt)" -ge 2
  while read -r opt val lo hi; do
    below=$(awk -v x="$lo" 'BEGIN { print (x == int(x)) ? x - 1 : x / 2 }')
    above=$(awk -v x="$hi" 'BEGIN { printf "%.15g", x + 1 }')
    at_parser $cmd "$opt" "$val" "$lo" accepted
    at_parser $cmd "$opt" "$val" "$hi" accepted
    at_parser $cmd "$opt" "$val" "$below" refused
    at_parser $cmd "$opt" "$val" "$above" refused
  done < ranges_$cmd.txt
done
check "bench documents at least 15 ranges" test "$(wc -l < ranges_bench.txt)" -ge 15
# one range per option: those render and bench both take document the same
join <(awk '{ print $1, $3, $4 }' ranges_render.txt | sort) \
     <(awk '{ print $1, $3, $4 }' ranges_bench.txt | sort) > shared.txt
check "render and bench share ranged options (--seed, --spp, --device, --threshold)" \
    test "$(wc -l < shared.txt)" -ge 4
while read -r opt rlo rhi blo bhi; do
  [ "$rlo $rhi" = "$blo $bhi" ] && ok || bad "$opt: render documents $rlo to $rhi, bench $blo to $bhi"
done < shared.txt

# bench --device as render's: a list or all, rendered on each device (two
# PoCL devices); the image does not depend on the split, so the accuracy
# columns equal one device's, and the devices column counts both
study() {  # study DIR DEVICE
  SPECMIP_TEST_MEET=2 POCL_DEVICES="basic basic" "$BIN" bench --scenes "$DATA/scenes/cornell.scene" \
    --size 64x64 --spp 64 --truth-spp 64 --modes ml --thresholds none --budgets none --repeat 1 \
    --no-charts --quiet --device "$2" --out "$1" 2> "$1.err"
}
csvcol() { awk -F, -v n="$2" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == n) c = i; next } { print $c }' "$1"; }
study one 0; check "bench --device 0: exit 0" test $? -eq 0
study two 0,1; rc=$?; check "bench --device 0,1: exit 0 ($(tail -1 two.err))" test $rc -eq 0
study all all; rc=$?; check "bench --device all: exit 0 ($(tail -1 all.err))" test $rc -eq 0
check "bench --device 0: one device rendered" test "$(csvcol one/bench.csv devices)" = 1
check "bench --device 0,1: both devices rendered" test "$(csvcol two/bench.csv devices)" = 2
check "bench --device all: both devices rendered" test "$(csvcol all/bench.csv devices)" = 2
for c in bias_ref_mean bias_ref_max bias_truth_mean err_mean; do
  check "bench on two devices: $c as on one" test "$(csvcol two/bench.csv $c)" = "$(csvcol one/bench.csv $c)"
done
check "bench meta names both devices" test "$(grep -c '^device:' two/bench_meta.txt)" = 2
POCL_DEVICES="basic basic" "$BIN" bench --ops --ops-items 1 --ops-iters 1 --out ops --device 0,1 2> err.txt
rc=$?
check "bench --ops times one device: a list is refused (exit 2)" test $rc -eq 2
check "bench --ops with a list: the error names --device" grep -q -- --device err.txt
expect bench --device 256 refused
finish
