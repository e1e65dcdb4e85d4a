#!/bin/bash
# Textures, opacity and normal maps on light subpaths on the OpenCL backend
# (kernels/lighttrace.cl, kernels/bdpt.cl with texture.clh texture_seen and
# the adjoint shading normal): --integrator light and bdpt against the CPU
# reference, image by image within a measured float tolerance, on the
# textured Cornell box, the Khronos avocado under an area light (a glTF's
# base colour, normal and roughness-metallic maps: the mix picked per
# vertex) and the cut-out lattice (an opacity mask in every ray of both
# subpaths and of the joins). That they converge to the path tracer is
# tests/test_bdpt_converge.c's (on the reference).
source "$(dirname "$0")/lib_cli.sh"
avg() { iinfo --stats "$1" | sed -n 's/^ *Stats Avg: *//p' | awk '{print $1 + $2 + $3}'; }

# Measured (AMD EPYC, PoCL 5, 24 x 24, 8 spp, seed 5): the largest channel's
# mean relative difference 0 and no pixel channel beyond 1e-3 on every scene
# and integrator below. The bounds are kernel_vs_cpu's of cli_bdpt_cl.sh
# (1e-4, 1 %): a texel, a mix pick or a factor the kernel misses moves many
# pixels by far more.
same_as_reference() { # NAME INTEGRATOR SCENE
    local name=$1 i=$2 scene=$3
    local a=(render "$scene" --integrator "$i" --width 24 --height 24 --spp 8 --seed 5 --quiet)
    "$BIN" "${a[@]}" -o "$T/$name-$i-cl.exr" 2> "$T/$name.err"
    check "$name, $i, OpenCL: exit 0 ($(head -c 300 "$T/$name.err"))" test $? -eq 0
    "$BIN" "${a[@]}" --backend cpu -o "$T/$name-$i-cpu.exr"
    check "$name, $i, reference: exit 0" test $? -eq 0
    check "$name, $i: not black" below 1e-3 "$(avg "$T/$name-$i-cl.exr")"
    local m b
    m=$(relavg "$T/$name-$i-cl.exr" "$T/$name-$i-cpu.exr")
    b=$(beyond "$T/$name-$i-cl.exr" "$T/$name-$i-cpu.exr")
    check "$name, $i: mean relative difference $m below 1e-4" below "$m" 1e-4
    check "$name, $i: share beyond 1e-3 relative $b below 1 %" below "$b" 0.01
}
# the avocado under a square lamp instead of its sky and sun
mkdir -p "$T/avocado"
cp "$DATA"/scenes/avocado/Avocado* "$T/avocado/"
sed -e '/^background /d' \
    -e 's/^light distant .*/material lamp emit d65 6\nquad lamp 1 3 1  -1 3 1  -1 3 -1  1 3 -1/' \
    "$DATA/scenes/avocado.scene" > "$T/avocado.scene"
check "the avocado's lamp is an area light" grep -q "^quad lamp" "$T/avocado.scene"
# the lattice alone: the veil's blend is a hash of each ray's bits, which
# the backends round alike only on camera paths' own rays
grep -v '^quad veil' "$DATA/scenes/cutout.scene" > "$T/lattice.scene"
# (the avocado's coated base is a picking type, which bdpt refuses; each
# scene and integrator is a kernel build of its own, so one each)
same_as_reference textured bdpt "$DATA/scenes/textured.scene"
same_as_reference avocado light "$T/avocado.scene"
same_as_reference lattice bdpt "$T/lattice.scene"
finish
