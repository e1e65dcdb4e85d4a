#!/bin/bash
# The bidirectional integrator's caustic scenes (docs/SCENES.md, docs/BDPT.md):
# scenes/water_caustic.scene, water_surface.ply and lamp_room.scene are what
# tools/gen_caustic_scenes.py writes; the pool is closed (no warning of an open
# glass); on each, the OpenCL kernel's bdpt image is the CPU reference's (the
# bound of cli_bdpt_cl.sh's glass: 1e-3 mean relative, 1 % of channels beyond
# 1e-3; before the conductor's eval was zero below its horizon on flat faces
# too, the kernel's lamp room was 10 % darker than the reference's); the lamp
# with its shade closed renders black (no light through the metal).
source "$(dirname "$0")/lib_cli.sh"

# 1. The committed files are the generator's output, byte for byte.
python3 "$ROOT/tools/gen_caustic_scenes.py" "$T/gen" > "$T/gen.list" ||
    { echo "FAIL: gen_caustic_scenes.py"; exit 1; }
for f in water_caustic.scene water_surface.ply lamp_room.scene; do
    check "$f is committed as generated" cmp -s "$T/gen/$f" "$DATA/scenes/$f"
done
check "the generator wrote 2 scenes" test "$(wc -l < "$T/gen.list")" -eq 2

# 2. Kernel against reference, and the pool closed.
for s in water_caustic lamp_room; do
    a=(render "$DATA/scenes/$s.scene" --integrator bdpt --mode ml --width 16 --height 16 --spp 4 --seed 5)
    "$BIN" "${a[@]}" -o "$T/$s-cl.exr" 2> "$T/$s.err"
    check "$s, OpenCL: exit 0" test $? -eq 0
    check "$s: no open glass" test "$(grep -c "not closed" "$T/$s.err")" -eq 0
    "$BIN" "${a[@]}" --quiet --backend cpu -o "$T/$s-cpu.exr"
    check "$s, reference: exit 0" test $? -eq 0
    check "$s: not black" below 1e-3 "$(iinfo --stats "$T/$s-cl.exr" | sed -n 's/^ *Stats Avg: *//p' | awk '{print $1 + $2 + $3}')"
    m=$(relavg "$T/$s-cl.exr" "$T/$s-cpu.exr")
    b=$(beyond "$T/$s-cl.exr" "$T/$s-cpu.exr")
    check "$s: mean relative difference $m below 1e-3" below "$m" 1e-3
    check "$s: share beyond 1e-3 relative $b below 1 %" below "$b" 0.01
done

# 3. The lamp's shade closed by a lid of its metal: no light leaves it, so
#    the path, light and bidirectional tracers' images are black on both
#    backends (a light subpath's splat through the rough metal's own face,
#    below its horizon, weighs nothing; a bdpt join is refused when a face
#    next to its light end, within the visibility test's last 1e-4 of the
#    segment, stands in the way, or when one end lies in the other's face
#    plane: both let light vertices inside the shade join the room, its
#    brightest pixel 3.6 at 16 x 16, 4 spp, and 1.6e-5 at 32 x 32, 16 spp).
sed 's/^# the glass egg.*/quad shade  0.765 0.500 0.745  0.835 0.500 0.745  0.835 0.500 0.815  0.765 0.500 0.815/' \
    "$DATA/scenes/lamp_room.scene" > "$T/closed.scene"
cp "$DATA/scenes/materials_sphere.ply" "$T/"
check "the closed lamp has its lid" grep -q "^quad shade  0.765 0.500" "$T/closed.scene"
for i in path light bdpt; do
    for b in opencl cpu; do
        r=(--width 16 --height 16 --spp 4 --seed 5)
        [ $i = bdpt ] && r=(--width 32 --height 32 --spp 16 --seed 7)
        "$BIN" render "$T/closed.scene" --integrator $i --backend $b "${r[@]}" \
            --quiet -o "$T/closed-$i-$b.exr"
        mx=$(oiiotool "$T/closed-$i-$b.exr" --printstats | awk '/Stats Max/ { print $3 + $4 + $5; exit }')
        check "closed lamp, $i, $b: black (max $mx)" test "$mx" = 0
    done
done
finish
