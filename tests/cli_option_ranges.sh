#!/bin/bash
# The shared option ranges (host/cli/cli_args.c spm_opt_ranges): render,
# bench and spectrum are fed the same values just inside and just outside each
# documented range; inside exits 0, outside exits 2 naming the option.
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
finish
