#!/bin/bash
# Files a scene references stay where the user pointed (host/util/paths.h):
# a mesh, a spectrum file, a glTF's buffers and images, an OBJ's MTL files
# and their maps resolve under the scene's folder, a folder given with
# --allow-path, or specmip's own spectra/ and scenes/. Each refusal is exit 2
# naming the referencing file and the reference, with the option that would
# allow it, and writes nothing; data: URIs, subfolders and --allow-path are
# accepted. Then the same refusals with the check before the import left out
# (SPECMIP_TEST_MESH_REFS=skip): the importer's child refuses on its own.
# Last, every file open under host/scene/ goes through the rule (a grep).
source "$(dirname "$0")/lib_cli.sh"

R=$T/root
O=$T/outside
mkdir -p "$R/sub/deeper" "$R/sub2" "$O"
python3 - "$R" "$O" <<'PY'
import base64, json, struct, sys
root, out = sys.argv[1], sys.argv[2]
tri = struct.pack('<9f', -1, 0, -1, 0, 0, 1, 1, 0, -1)
def gltf(uri, image=None):
    g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
         "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
         "buffers": [{"uri": uri, "byteLength": 36}],
         "bufferViews": [{"buffer": 0, "byteLength": 36}],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [-1, 0, -1], "max": [1, 0, 1]}]}
    if image:
        g["images"] = [{"uri": image}]
        g["textures"] = [{"source": 0}]
        g["materials"] = [{"name": "m", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
        g["meshes"][0]["primitives"][0]["material"] = 0
    return json.dumps(g)
for d in (root + "/sub", root + "/sub2", out):
    open(d + "/tri.bin", "wb").write(tri)
models = {
    "abs.gltf": gltf(out + "/tri.bin"),
    "parent.gltf": gltf("../outside/tri.bin"),
    "link.gltf": gltf("lnk/tri.bin"),
    "percent.gltf": gltf("%2e%2e/%2E%2e/outside/tri.bin"),
    "image.gltf": gltf("sub/tri.bin", "../outside/tex.png"),
    "data.gltf": gltf("data:application/octet-stream;base64," + base64.b64encode(tri).decode()),
    "inside.gltf": gltf("sub/tri.bin"),
    "sub/deeper/up.gltf": gltf("../../sub2/tri.bin"),
}
for name, text in models.items():
    open(root + "/" + name, "w").write(text)
obj = "v -1 0 -1\nv 0 0 1\nv 1 0 -1\nusemtl m\nf 1 2 3\n"
open(root + "/mtllib.obj", "w").write("mtllib ../outside/m.mtl\n" + obj)
open(root + "/map.obj", "w").write("mtllib map.mtl\n" + obj)
open(root + "/map.mtl", "w").write("newmtl m\nKd 0.5 0.5 0.5\nmap_Kd -s 1 1 1 ../outside/tex.png\n")
open(out + "/m.mtl", "w").write("newmtl m\nKd 0.5 0.5 0.5\n")
open(out + "/white.csv", "w").write("wavelength,value\n380,0.5\n780,0.5\n")
PY
# a 2x2 PNG outside, so that a refused image is one that could be read
oiiotool --pattern constant:color=1,0,0 2x2 3 -d uint8 -o "$O/tex.png" 2>/dev/null ||
    bad "oiiotool made no test image"
ln -s ../outside "$R/lnk"

# scene MESH [SPECTRUM_FILE]: a lit scene in $R that loads MESH
scene() {
    cat > "$R/s.scene" <<EOF
image 16 16
camera position 0 1 -3 direction 0 0 1 fov 40
spectrum flat ${2:-equal}
material wall reflect flat 0.5
material light emit flat 10
quad light -1 2 -1  1 2 -1  1 2 1  -1 2 1
mesh $1 material wall
EOF
}
# refused WHAT REF WHERE [ENV...]: the render fails with exit 2, naming the
# scene, where the reference is written and the reference; suggests
# --allow-path; writes no image.
refused() {
    local what=$1 ref=$2 where=$3
    shift 3
    rm -f "$T/o.png"
    env "$@" "$BIN" render "$R/s.scene" --backend cpu --spp 1 -o "$T/o.png" 2> "$T/err" > /dev/null
    local rc=$?
    [ $rc -eq 2 ] || { bad "$what: rc $rc, want 2: $(head -c 400 "$T/err")"; return; }
    grep -qF "s.scene:" "$T/err" && grep -qF -- "$where" "$T/err" && grep -qF -- "$ref" "$T/err" &&
        grep -qF -- "--allow-path" "$T/err" && ok ||
        bad "$what: the error does not name s.scene, '$where', '$ref' and --allow-path: $(cat "$T/err")"
    [ ! -e "$T/o.png" ] && ok || bad "$what: an image was written"
}
accepted() {
    local what=$1
    shift
    rm -f "$T/o.png"
    "$BIN" render "$R/s.scene" --backend cpu --spp 1 -o "$T/o.png" --quiet "$@" 2> "$T/err" > /dev/null &&
        [ -s "$T/o.png" ] && ok || bad "$what: not rendered: $(head -c 400 "$T/err")"
}

# 1. Refusals, named by the check before the import
scene abs.gltf;      refused "absolute buffer URI" "'$O/tri.bin'" "abs.gltf: buffers[0].uri"
scene parent.gltf;   refused "../ out of the root" "'../outside/tri.bin'" "parent.gltf: buffers[0].uri"
scene link.gltf;     refused "a link inside the root to outside" "(to $(cd "$O" && pwd -P)/tri.bin)" \
                         "link.gltf: buffers[0].uri"
scene percent.gltf;  refused "percent-encoded ../" "written '%2e%2e/%2E%2e/outside/tri.bin'" \
                         "percent.gltf: buffers[0].uri"
scene image.gltf;    refused "glTF image outside" "'../outside/tex.png'" "image.gltf: images[0].uri"
scene mtllib.obj;    refused "MTL file outside" "'../outside/m.mtl'" "mtllib.obj:1"
scene map.obj;       refused "MTL map outside" "'../outside/tex.png'" "map.mtl:3"
scene ../outside/tri.bin; refused "mesh outside" "'../outside/tri.bin'" "s.scene:7:6"
scene lnk/tri.bin;   refused "mesh through a link" "'lnk/tri.bin'" "s.scene:7:6"
scene inside.gltf "file $O/white.csv"
refused "spectrum file outside" "'$O/white.csv'" "s.scene:3:"

# 2. Accepted: data: URIs, subfolders, a reference up and down inside the
# root, the project's spectra/, --allow-path
scene data.gltf;     accepted "data: URI"
scene inside.gltf;   accepted "buffer in a subfolder"
scene sub/deeper/up.gltf; accepted "../ that stays inside the root"
scene inside.gltf "file colorchecker_n_ohta.csv column white_9_5"
accepted "a spectrum from specmip's spectra/"
scene parent.gltf;   accepted "--allow-path" --allow-path "$O"
scene link.gltf;     accepted "--allow-path through a link" --allow-path "$R/lnk"
"$BIN" render "$R/s.scene" --backend cpu --allow-path "$T/none" -o "$T/o.png" 2> "$T/err"
[ $? -eq 2 ] && grep -qF -- "--allow-path $T/none" "$T/err" && ok ||
    bad "--allow-path of a missing folder: $(cat "$T/err")"

# 3. The importer's child on its own (the check before the import skipped):
# what Assimp opens and the images it reads are refused there too
scene mtllib.obj; refused "child: MTL file outside" "(to $(cd "$O" && pwd -P)/m.mtl)" \
    "a file its importer asked for" SPECMIP_TEST_MESH_REFS=skip
scene parent.gltf; refused "child: glTF buffer outside" "(to $(cd "$O" && pwd -P)/tri.bin)" \
    "a file its importer asked for" SPECMIP_TEST_MESH_REFS=skip
scene map.obj; refused "child: MTL map outside" "'../outside/tex.png'" "map.obj: image" \
    SPECMIP_TEST_MESH_REFS=skip

# 4. No reader under host/scene/ opens a file but through the rule: the
# openers below appear only on the lines listed (each takes a checked spm_file)
openers='(^|[^_a-z])fopen\(|spm_fopen_input\(|[^_a-z]open\(|ImageInput::open|aiImportFile|spm_csv_load\(|spm_spectrum_load\(|spm_fluor_load_donaldson\(|spm_texture_mean_file\(|spm_texture_read_file\(|spm_texture_read_alpha_file\(|spm_texture_read_channel_file\(|spm_texture_read\(|spm_texture_read_one\(|spm_lex_open\('
allowed=(
    'mesh_import.c:.*aiImportFileEx\(file->path, aiProcess_Triangulate, &io\)'
    'texture_io.cpp:.*ImageInput::open\(src->file->path, unassoc' # a file checked by its caller
    'texture_io.cpp:.*ImageInput::open\(std::string\("embedded."\)' # bytes in memory
    'texture_io.cpp:.*return spm_texture_read(_one)?\(&src,' # the _file forms: their callers'
    'mesh_texture.c:.*spm_texture_mean_file\(&file,'
    'mesh_texture.c:.*spm_texture_read\(&src, SPM_IMAGE_COLOUR,' # spm_mesh_map_image: a path checked again, or bytes
    'mesh_nmap.c:.*spm_texture_read\(&src, SPM_IMAGE_DATA,' # the same
    'mesh_texture_io.cpp:.*spm_texture_read_file\(file, &rgb,'
    'scene_texture.c:.*spm_texture_read_file\(&f, &rgb,'
    'scene_texture.c:.*spm_texture_read_alpha_file\(&x->file, 0, &a,' # checked at the statement
    'mesh_alpha.c:.*spm_texture_read_one\(&src, base,' # spm_mesh_map_image, as above
    'mesh_metalrough.c:.*spm_texture_read_one\(&src, -1 - c,' # the same
    'envmap.c:.*spm_texture_read_file\(f, &rgb,'
    'scene_parse.c:.*spm_spectrum_load\(d->file.path,'
    'scene_parse.c:.*spm_fluor_load_donaldson\(path.path,'
    'scene_parse.c:.*spm_lex_open\(&p.lx, file, err\)'
    'scene_parse.c:.*spm_lex_open\(&p->lx, &inc, p->err\)'
    'scene_minilight.c:.*spm_lex_open\(&p.lx, file, err\)'
    'pbrt_spectra.c:.*spm_spectrum_load\(spm_data_path\(rel, path, sizeof path\)'
    'fluor.c:.*spm_csv_load\(path, &csv, err\)'
    'sky.c:.*spm_csv_load\(path, t, err\)' # the program's own spectra/ (spm_data_path)
    'rgb2spec_table.c:.*fopen\(path, "rb"\)' # the program's own cache file, no scene's reference
)
(cd "$ROOT/host/scene" && grep -nE "$openers" *.c *.cpp | grep -vE '^[^:]+:[0-9]+:\s*(/?\*|//)' |
    grep -vE '^[^:]+:[0-9]+:(int|FILE|static|extern) ') > "$T/opens"
for a in "${allowed[@]}"; do
    grep -qE "^${a%%:*}:[0-9]+:${a#*:}" "$T/opens" && ok || bad "listed opener not found: $a"
    grep -vE "^${a%%:*}:[0-9]+:${a#*:}" "$T/opens" > "$T/rest"
    mv "$T/rest" "$T/opens"
done
[ ! -s "$T/opens" ] && ok || bad "host/scene opens files without the path rule: $(cat "$T/opens")"
finish
