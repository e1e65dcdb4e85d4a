#!/bin/bash
# specmip render --film / --resume (docs/RENDERING.md): 8 spp kept, then
# resumed to 16, is bit for bit the 16-spp render, on the OpenCL backend, the
# CPU reference and two PoCL devices; a resume of another scene, mode, size or
# seed is refused naming what differs, as are a truncated or corrupt film and
# an EXR that names none (exit 2, nothing written); a full disk (a file size
# limit) leaves the previous film as it was.
source "$(dirname "$0")/lib_cli.sh"
SPIKY=$DATA/scenes/cornell_spiky.scene
# exr_int FILE NAME: an integer attribute of an EXR header
exr_int() { oiiotool --info -v "$1" 2> /dev/null | sed -n "s/^ *$2: \([0-9-]*\)$/\1/p"; }
film_samples() { grep -a -m1 '^samples=' "$1" | cut -d= -f2; }
said() { grep -q "$1" "$T/err" || { echo "  stderr: $(tail -3 "$T/err")"; false; }; }
not_said() { ! grep -q "$1" "$T/err"; }
no_temps() { [ -z "$(find "$T" -name '*spmtmp*')" ]; }

# 128x128: 4 spp per pass (spm_spp_per_pass), so 8 spp ends on the pass grid.
R=(render "$SPIKY" --width 128 --height 128 --seed 3 --quiet)

# resumed WHAT ARGS...: 8 spp kept, resumed to 16, against one render to 16.
resumed() {
    local what=$1
    shift
    "$@" --spp 16 -o "$T/one.exr"
    check "$what: one render to 16" test $? -eq 0
    "$@" --spp 8 --film -o "$T/r.exr" -o "$T/r.png"
    check "$what: 8 spp with its film" test $? -eq 0 -a -s "$T/r.exr.film"
    check "$what: the film holds 8 spp" test "$(film_samples "$T/r.exr.film")" = 8
    check "$what: 8 spp is not yet the image" other_pixels "$T/one.exr" "$T/r.exr"
    "$@" --spp 16 --resume "$T/r.exr" 2> "$T/err"
    check "$what: resumed to 16" test $? -eq 0
    check "$what: bit for bit one render to 16" same_pixels "$T/one.exr" "$T/r.exr"
    check "$what: the EXR says 16 spp" test "$(exr_int "$T/r.exr" samplesPerPixel)" = 16
    check "$what: the film holds 16 spp" test "$(film_samples "$T/r.exr.film")" = 16
    check "$what: no warning of another render" not_said "not bit-identical"
}
resumed "one device" "$BIN" "${R[@]}"
resumed "CPU reference" "$BIN" "${R[@]}" --backend cpu
# Two devices of PoCL, the passes shared out as they come (both take some).
SPECMIP_TEST_MEET=2 POCL_DEVICES="pthread basic" resumed "two devices" "$BIN" "${R[@]}" --device all

# A spectral render keeps its bins in the film too: both EXRs bit for bit.
S=("$BIN" "${R[@]}" --mode truth)
"${S[@]}" --spp 16 -o "$T/s1.exr" -o "$T/s1.spectral.exr"
"${S[@]}" --spp 8 --film -o "$T/s.spectral.exr" -o "$T/s.exr"
check "spectral: a film with its bins" grep -aq '^layer=spectral f64 80$' "$T/s.spectral.exr.film"
"${S[@]}" --spp 16 --resume "$T/s.spectral.exr" -o "$T/s.spectral.exr" -o "$T/s.exr"
check "spectral: resumed to 16" test $? -eq 0
check "spectral: the spectral EXR bit for bit" same_pixels "$T/s1.spectral.exr" "$T/s.spectral.exr"
check "spectral: the RGB EXR bit for bit" same_pixels "$T/s1.exr" "$T/s.exr"

# A film off the pass grid (64x64: 16 spp per pass, 8 spp is half a pass)
# is continued, with a warning that it is not bit-identical.
"$BIN" "${R[@]}" --width 64 --height 64 --spp 8 --film -o "$T/g.exr"
"$BIN" "${R[@]}" --width 64 --height 64 --spp 16 --resume "$T/g.exr" 2> "$T/err"
check "off the grid: resumed" test $? -eq 0 -a "$(film_samples "$T/g.exr.film")" = 16
check "off the grid: warned" said "not a whole number of this render's passes of 16"

# refused WHAT MESSAGE ARGS...: a resume of r.exr (16 spp) with ARGS is
# refused, naming what differs; neither the EXR nor its film is touched.
cp "$T/r.exr.film" "$T/keep.film"
refused() {
    local what=$1 msg=$2
    shift 2
    cp "$T/r.exr" "$T/before.exr" && cp "$T/r.exr.film" "$T/before.film"
    "$BIN" "$@" --resume "$T/r.exr" 2> "$T/err"
    check "$what: exit 2" test $? -eq 2
    check "$what: says what differs" said "$msg"
    check "$what: EXR untouched" cmp -s "$T/r.exr" "$T/before.exr"
    check "$what: film untouched" cmp -s "$T/r.exr.film" "$T/before.film"
}
refused "another mode" "r.exr.film: the film is of another render: mode ml (this render: truth)" \
    "${R[@]}" --spp 24 --mode truth
refused "another size" "size 128x128 (this render: 128x96)" "${R[@]}" --spp 24 --height 96
refused "another seed" "seed 3 (this render: 4)" "${R[@]}" --spp 24 --seed 4
refused "another scene" "the scene's contents (its fingerprint scene" \
    render "$DATA/scenes/cornell.scene" --width 128 --height 128 --seed 3 --quiet --spp 24
refused "another threshold" "threshold 2 (this render: 3)" "${R[@]}" --spp 24 --threshold 3
refused "no more samples" "holds 16 samples per pixel already" "${R[@]}" --spp 16

# A truncated film, a corrupt one, an EXR without a film: refused naming the file.
head -c 100000 "$T/keep.film" > "$T/r.exr.film"
refused "truncated film" "r.exr.film: truncated" "${R[@]}" --spp 24
cp "$T/keep.film" "$T/r.exr.film"
printf '\x01' | dd of="$T/r.exr.film" bs=1 seek=300000 conv=notrunc status=none
refused "corrupt film" "r.exr.film: corrupt: its checksum does not match" "${R[@]}" --spp 24
cp "$T/keep.film" "$T/r.exr.film"
"$BIN" "${R[@]}" --spp 4 -o "$T/plain.exr"
"$BIN" "${R[@]}" --spp 8 --resume "$T/plain.exr" 2> "$T/err"
check "no film: exit 2" test $? -eq 2
check "no film: says so" said "plain.exr: names no film to resume from"
"$BIN" "${R[@]}" --spp 8 --film -o "$T/x.png" 2> "$T/err"
check "--film without an EXR: exit 2" test $? -eq 2
check "--film without an EXR: says so" said "need an .exr output"
check "--film without an EXR: nothing written" test ! -e "$T/x.png"

# A full disk (a file size limit of 60 KiB: the 64x48 EXR fits, its 74 KB
# film does not): exit 1 naming the film, the previous film kept as it was.
F=(render --backend cpu --width 64 --height 48 --quiet)
"$BIN" "${F[@]}" --spp 8 --film -o "$T/d.exr" && cp "$T/d.exr.film" "$T/d.keep"
(trap '' XFSZ; ulimit -f 60; exec "$BIN" "${F[@]}" --spp 16 --resume "$T/d.exr") 2> "$T/err"
check "full disk: exit 1" test $? -eq 1
check "full disk: names the film" said "d.exr.film: cannot write the film: File too large (the previous film"
check "full disk: previous film kept" cmp -s "$T/d.exr.film" "$T/d.keep"
check "full disk: no temporary file" no_temps
"$BIN" "${F[@]}" --spp 16 --resume "$T/d.exr" 2> "$T/err"
check "full disk: resumed later from the kept film" test $? -eq 0 -a "$(film_samples "$T/d.exr.film")" = 16

finish
