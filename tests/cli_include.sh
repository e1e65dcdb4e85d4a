#!/bin/bash
# include FILE: a scene split over files renders the same pixels as the scene
# written in one; an included file's errors name it and where it was
# included; a cycle, a missing file and a file outside the scene's folder are
# refused (exit 2, nothing written). The CPU reference renders: no device.
source "$(dirname "$0")/lib_cli.sh"

mkdir -p "$T/s/parts"
cat > "$T/s/one.scene" <<'S'
image 16 16
camera position 0 0 -4 direction 0 0 1 fov 60
spectrum white equal
material white reflect white 0.8
material lamp reflect white emit white 10
quad lamp -1 2 -1  1 2 -1  1 2 1  -1 2 1
quad white -3 -1 -3  -3 -1 3  3 -1 3  3 -1 -3
S
head -4 "$T/s/one.scene" > "$T/s/main.scene"
echo "include parts/light.scene" >> "$T/s/main.scene"
sed -n 5,6p "$T/s/one.scene" > "$T/s/parts/light.scene"
echo 'include "floor.scene"' >> "$T/s/parts/light.scene"   # relative to parts/
sed -n 7p "$T/s/one.scene" > "$T/s/parts/floor.scene"
R=(--backend cpu --spp 4 --seed 3 --quiet)
"$BIN" render "$T/s/one.scene" "${R[@]}" -o "$T/one.exr" && ok || bad "one file: not rendered"
"$BIN" render "$T/s/main.scene" "${R[@]}" -o "$T/main.exr" && ok || bad "included: not rendered"
same_pixels "$T/one.exr" "$T/main.exr" && ok || bad "included scene differs from the one file"

# refused FILE_CONTENTS TEXT...: floor.scene replaced; exit 2, each TEXT said, nothing written
refused() {
    local content=$1
    shift
    echo "$content" > "$T/s/parts/floor.scene"
    rm -f "$T/bad.exr"
    "$BIN" render "$T/s/main.scene" "${R[@]}" -o "$T/bad.exr" 2> "$T/err"
    local rc=$?
    [ $rc -eq 2 ] && ok || bad "'$content': rc $rc, want 2"
    for t in "$@"; do
        grep -qF -- "$t" "$T/err" && ok || bad "'$content': '$t' not said: $(cat "$T/err")"
    done
    [ ! -e "$T/bad.exr" ] && ok || bad "'$content': an image was written"
}
refused "quad nosuch 0 0 0  1 0 0  1 1 0  0 1 0" "parts/floor.scene:1:6: unknown material 'nosuch'" \
    "(included at $T/s/parts/light.scene:3:1) (included at $T/s/main.scene:5:1)"
refused "include ../main.scene" "include '../main.scene': a cycle"
refused "include floor.scene" "include 'floor.scene': a cycle"
refused "include nothing.scene" "included file 'nothing.scene' not found"
refused "include ../../outside.scene" "'../../outside.scene' leads outside the scene's folder" \
    "--allow-path"
refused "include" "expected an included file's name"
finish
