#!/bin/bash
# The kernels are compiled at run time from a source tree (SPECMIP_DATA); one
# whose contract headers (include/) differ from those the binary was built
# with is refused with an error naming the header, before anything renders,
# instead of running kernels whose structs and arguments do not match the
# host's. A copy of the tree as built renders.
# usage: bash tests/cli_kernel_tree.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

tree() {  # tree NAME: a copy of the data the renderer reads, in $T/NAME
  mkdir -p "$T/$1" && cp -r "$SPECMIP_DATA"/{include,kernels,spectra,scenes} "$T/$1/"
}
R=(render --spp 1 --width 16 --height 16 --quiet)

tree same
SPECMIP_DATA=$T/same "$BIN" "${R[@]}" -o "$T/same.exr" 2> "$T/same.err" && [ -s "$T/same.exr" ] &&
  ok || bad "a copy of the tree as built: $(cat "$T/same.err")"

# a struct of the contract one field longer (a newer tree), and a header gone
tree newer
sed -i '0,/^typedef struct {/s//typedef struct {\n    uint newer_field;/' "$T/newer/include/spm_shared.h"
cmp -s "$SPECMIP_DATA/include/spm_shared.h" "$T/newer/include/spm_shared.h" && bad "the edit changed nothing"
tree gone
rm "$T/gone/include/spm_rng.h"
for t in newer:spm_shared.h:differs gone:spm_rng.h:missing; do
  IFS=: read -r name header word <<< "$t"
  SPECMIP_DATA=$T/$name "$BIN" "${R[@]}" -o "$T/$name.exr" 2> "$T/$name.err"
  rc=$?
  [ $rc -ne 0 ] && [ $rc -lt 128 ] && [ ! -e "$T/$name.exr" ] &&
    grep -q "$T/$name/include/$header: $word" "$T/$name.err" &&
    ok || bad "$name tree: exit $rc, $(cat "$T/$name.err")"
done
finish
