#!/bin/bash
# Quiet stderr: `--quiet` on a mesh scene's first render (an empty PoCL kernel
# cache) prints nothing at all, while without it the mesh notes are there; a
# file's material names are listed once in a binding error however often the
# file repeats them; PoCL's kernel-cache warning (a compile during the timed
# render) is said with --stats only.
# usage: bash tests/cli_quiet.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
export POCL_CACHE_DIR=$T/kcache
S=(--width 16 --height 16 --spp 1)

# 1. --quiet is quiet; without it the notes appear (so the check can see them)
"$BIN" render "$ROOT/scenes/materials.scene" "${S[@]}" --quiet -o "$T/q.png" 2> "$T/q.err"
check "quiet: renders" test $? -eq 0
check "quiet: stderr empty on a mesh scene ($(head -c 300 "$T/q.err"))" test ! -s "$T/q.err"
"$BIN" render "$ROOT/scenes/materials.scene" "${S[@]}" -o "$T/n.png" 2> "$T/n.err"
check "not quiet: the mesh notes are printed" \
    grep -q 'materials_sphere.ply: 528 triangles, bounding box' "$T/n.err"

# 2. a glTF whose materials repeat a name (as exported files do): listed once
python3 - "$ROOT/tools" "$T/rep.gltf" << 'PY'
import sys
sys.path.insert(0, sys.argv[1])
import gen_meshes as g
quad = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
mats = [{'name': n, 'pbrMetallicRoughness': {'baseColorFactor': [0.5, 0.5, 0.5, 1],
                                             'metallicFactor': 0.0}}
        for n in ('paint', 'paint', 'glaze', 'paint')]
doc, buf = g.gltf_doc(quad, [([0, 1, 2], 0), ([0, 2, 3], 1), ([0, 1, 3], 2), ([1, 2, 3], 3)],
                      [{'mesh': 0}], [0], mats)
g.write_gltf(sys.argv[2], doc, buf)
PY
cat > "$T/rep.scene" << 'E'
camera position 0 0 -4 direction 0 0 1 fov 60
spectrum white equal
material wall reflect white 0.5
background both white 1
mesh rep.gltf bind nosuch wall
E
"$BIN" render "$T/rep.scene" "${S[@]}" --backend cpu --quiet -o "$T/rep.png" 2> "$T/rep.err"
check "binding: refused (exit 2)" test $? -eq 2
check "binding: each name once ($(cat "$T/rep.err"))" \
    grep -q "rep.gltf has no material 'nosuch' (it has 'paint', 'glaze')" "$T/rep.err"

# 3. the kernel cache growing during the render (here another process's file,
#    which looks the same) is warned about with --stats only
cache_grows() {  # cache_grows OUT ARGS...: a 4 s render; a file joins the cache once it renders
    rm -f "$T/$1.err"
    ( for _ in $(seq 600); do [ -s "$T/$1.err" ] && break; sleep 0.1; done  # the progress line
      echo x > "$POCL_CACHE_DIR/other-process" ) &
    "$BIN" render "$ROOT/scenes/cornell.scene" --width 32 --height 32 --spp 1000000 --time 4 \
        --progress -o "$T/t.png" "${@:2}" > /dev/null 2> "$T/$1.err"
    wait
    rm -f "$POCL_CACHE_DIR/other-process"
}
cache_grows plain
check "cache: no warning without --stats ($(head -c 300 "$T/plain.err"))" \
    eval "! grep -qi 'kernel cache' '$T/plain.err'"
cache_grows stats --stats
check "cache: the warning with --stats" grep -q "PoCL's kernel cache .* gained" "$T/stats.err"
finish
