#!/usr/bin/env bash
# Outputs are checked before rendering, on the CPU reference (no OpenCL, so the
# sanitizer build runs it too): a name that is only an extension, and one file
# given twice however it is spelt, exit 2 with nothing written; a symbolic link
# is written through, its target replaced, the link kept.
source "$(dirname "$0")/lib_cli.sh"

R=(render --backend cpu --spp 1 --width 16 --height 16 --quiet)
# A render that would outlast `timeout 20`: exit 2 (not 124) shows the check
# came before any rendering.
SLOW=(render --backend cpu --spp 1000000 --width 64 --height 64 --quiet)
no_temps() { [ -z "$(find "$@" -name '*spmtmp*' -o -name '.specmip-probe*')" ]; }
is_png() { head -c 4 "$1" | grep -q PNG; }

# refused WHAT MESSAGE OUTPUT-ARGS...: exit 2 before rendering, MESSAGE said,
# no file but the old ones in $T/w.
refused() {
    local what=$1 msg=$2
    shift 2
    (cd "$T/w" && timeout 20 "$BIN" "${SLOW[@]}" "$@" 2> "$T/err")
    local rc=$?
    check "$what: exit 2" test $rc -eq 2
    check "$what: message" grep -q -- "$msg" "$T/err"
    check "$what: nothing written" test "$(ls -A "$T/w" | tr '\n' ' ')" = "$(cat "$T/before")"
}

mkdir -p "$T/w/sub" "$T/elsewhere"
echo old > "$T/w/a.png"
ln -s a.png "$T/w/link.png"
ln -s link.png "$T/w/link2.png"
ls -A "$T/w" | tr '\n' ' ' > "$T/before"

# 1. A name that is only an extension.
refused "-o .png" "no file name before the extension" -o .png
refused "-o sub/.exr" "no file name before the extension" -o sub/.exr

# 2. One file twice, however spelt.
refused "a.png twice" "a.png: given twice" -o a.png -o a.png
refused "./a.png and a.png" "the same file" -o ./a.png -o a.png
refused "absolute and relative" "the same file" -o "$T/w/a.png" -o a.png
refused "sub/../a.png" "the same file" -o a.png -o sub/../a.png
refused "double slash" "the same file" -o "$T/w//b.exr" -o "$T/w/b.exr"
refused "a link and its target" "the same file" -o link.png -o a.png
refused "a chain of links" "the same file" -o link2.png -o a.png
# ... and different files are fine, the default outputs too.
(cd "$T/elsewhere" && "$BIN" "${R[@]}" -o a.png -o sub.png -o a.exr && "$BIN" "${R[@]}")
check "different names: exit 0" test $? -eq 0
check "default outputs written" test -s "$T/elsewhere/specmip.png" -a -s "$T/elsewhere/specmip.exr"

# 3. A symbolic link is written through: the link stays, its target is
#    replaced, the temporary file is made next to the target.
ln -s ../elsewhere/t.png "$T/w/far.png"
echo old > "$T/elsewhere/t.png"
"$BIN" "${R[@]}" -o "$T/w/far.png" -o "$T/w/link2.png"
check "links: exit 0" test $? -eq 0
check "link kept" test -L "$T/w/far.png" -a "$(readlink "$T/w/far.png")" = ../elsewhere/t.png
check "chain kept" test -L "$T/w/link2.png" -a -L "$T/w/link.png"
check "target replaced" is_png "$T/elsewhere/t.png"
check "chain's target replaced" is_png "$T/w/a.png"
check "no temporary file" no_temps "$T"
# A dangling link: its target is created.
ln -s ../elsewhere/new.png "$T/w/dangling.png"
"$BIN" "${R[@]}" -o "$T/w/dangling.png"
check "dangling link: exit 0" test $? -eq 0
check "dangling link: target created" is_png "$T/elsewhere/new.png"
check "dangling link: kept" test -L "$T/w/dangling.png"
# A link into a directory that does not exist: refused before rendering.
ln -s ../nowhere/x.png "$T/w/broken.png"
ls -A "$T/w" | tr '\n' ' ' > "$T/before"
refused "link to a missing directory" "broken.png: symbolic link to .*whose directory does not exist" \
    -o broken.png
# A link to a directory.
ln -s ../elsewhere "$T/w/dir.png"
ls -A "$T/w" | tr '\n' ' ' > "$T/before"
refused "link to a directory" "dir.png: is a directory" -o dir.png

# The other formats OpenImageIO writes: .hdr (Radiance RGBE) is linear like the
# EXR, negative values dropped, each channel rounded to an 8-bit mantissa shared
# with the pixel's largest: on this noisy 16x16 image the channel means moved by
# 1.3 % at most (3 % allowed; a tone-mapped or sRGB-encoded file is off by far
# more). .jpg holds the PNG's tone-mapped 8-bit codes under JPEG's loss: channel
# means within 3.5 codes measured (6 allowed; linear values would be off by tens).
avgs() { oiiotool "$@" --printstats 2> /dev/null | sed -n 's/^ *Stats Avg: *//p' | awk '{ print $1, $2, $3 }'; }
means_within() {  # means_within "A0 A1 A2" "B0 B1 B2" REL ABS: |a - b| <= REL * a + ABS per channel
    local a=($1) b=($2) i
    [ ${#a[@]} -eq 3 ] && [ ${#b[@]} -eq 3 ] || return 1
    for i in 0 1 2; do
        near "${a[$i]}" "${b[$i]}" "$(awk -v v="${a[$i]}" -v r="$3" -v t="$4" 'BEGIN { print r * v + t }')" || return 1
    done
}
(cd "$T/elsewhere" && "$BIN" "${R[@]}" -o f.exr -o f.hdr -o f.png -o f.jpg)
check "hdr and jpg: exit 0" test $? -eq 0
exr=$(avgs "$T/elsewhere/f.exr" --clamp:min=0) hdr=$(avgs "$T/elsewhere/f.hdr")
check "hdr: linear, the EXR's means ($hdr against $exr)" means_within "$exr" "$hdr" 0.03 0
png=$(avgs "$T/elsewhere/f.png") jpg=$(avgs "$T/elsewhere/f.jpg")
check "jpg: the PNG's codes ($jpg against $png)" means_within "$png" "$jpg" 0 6

finish
