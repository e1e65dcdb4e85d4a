#!/bin/bash
# Small command-line conveniences: 'specmip SCENE' renders; '--name=value'
# equals '--name value'; --width or --height alone keeps the scene's aspect
# ratio (both: exactly that size); 'specmip spectrum NAME.csv' finds the
# bundled spectra/ file.
# usage: bash tests/cli_small_options.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
cd "$T"
R=(--backend cpu --spp 1 --quiet)
size() { oiiotool --info "$1" 2>/dev/null | sed -n 's/.*: *\([0-9]*\) x *\([0-9]*\),.*/\1x\2/p'; }

# A 2:1 scene: the bundled Cornell box at 64x32.
sed 's/^image .*/image 64 32/' "$DATA/scenes/cornell.scene" > wide.scene
grep -q '^image 64 32$' wide.scene && ok || bad "generated scene has no 'image 64 32' line"

# 1. specmip SCENE: the same image as specmip render SCENE
"$BIN" render wide.scene "${R[@]}" -o ref.exr; rc=$?
[ $rc -eq 0 ] && ok || bad "render wide.scene exited $rc"
"$BIN" wide.scene "${R[@]}" -o bare.exr 2> bare.err; rc=$?
[ $rc -eq 0 ] && ok || bad "specmip wide.scene exited $rc: $(cat bare.err)"
check "specmip SCENE renders what render SCENE does" same_pixels ref.exr bare.exr
# a typo of a command is still an unknown command, not a scene
"$BIN" rendr > /dev/null 2> typo.err; rc=$?
[ $rc -eq 2 ] && grep -q "unknown command 'rendr'" typo.err && ok || bad "rendr: exit $rc"

# 2. --name=value
"$BIN" render wide.scene --backend=cpu --spp=1 --quiet -o eq.exr; rc=$?
[ $rc -eq 0 ] && ok || bad "--spp=1 exited $rc"
check "--spp=1 renders what --spp 1 does" same_pixels ref.exr eq.exr
"$BIN" render wide.scene --backend=cpu --spp=2 --quiet -o eq2.exr
check "--spp=2 is not --spp=1" other_pixels ref.exr eq2.exr
"$BIN" render wide.scene --backend=cpu --spp=0 --quiet -o x.exr 2> zero.err; rc=$?
[ $rc -eq 2 ] && grep -q -- "--spp" zero.err && ok || bad "--spp=0: exit $rc, $(cat zero.err)"

# 3. one side alone keeps the aspect ratio; both give exactly that size
for a in "--width 32:32x16" "--height 8:16x8" "--width 33:33x17" "--width 32 --height 32:32x32"; do
  args=${a%%:*} want=${a##*:}
  # shellcheck disable=SC2086
  "$BIN" render wide.scene "${R[@]}" $args -o s.exr; rc=$?
  got=$(size s.exr)
  [ $rc -eq 0 ] && [ "$got" = "$want" ] && ok || bad "$args: exit $rc, size '$got', want $want"
done

# 4. spectrum finds a bundled file by its bare name, as scenes do
"$BIN" spectrum illuminant_F11.csv --emission --json > f11.json 2> f11.err; rc=$?
[ $rc -eq 0 ] && ok || bad "spectrum illuminant_F11.csv exited $rc: $(cat f11.err)"
"$BIN" spectrum "$DATA/spectra/illuminant_F11.csv" --emission --json > f11ref.json
y=$(jnum f11.json '.XYZ[0]'); yr=$(jnum f11ref.json '.XYZ[0]')
check "bundled F11 is the same spectrum as by its path" num "$y" == "$yr"
"$BIN" spectrum no_such_spectrum.csv > /dev/null 2> miss.err; rc=$?
[ $rc -eq 2 ] && grep -q no_such_spectrum.csv miss.err && ok || bad "missing spectrum: exit $rc"
finish
