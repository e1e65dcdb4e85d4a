#!/usr/bin/env bash
# glTF KHR_lights_punctual (docs/SCENE_FORMAT.md, mesh): a point, a spot and a
# directional light written by tests/gltf_lights.py, each placed by a node
# under a parent, over a Lambertian floor (rho 0.5, the mesh's `material`),
# on both backends against their closed forms: L = rho I cos(theta) / (pi
# d^2) with I the candela times the luminance of `color`, the spot's times
# glTF's falloff (the square of a ramp in cos from the outer to the inner
# angle), rho E cos(theta) / pi for the lux of a directional light. Each ring
# of pixels (2 wide about the centre) within 1 % of the peak: measured worst
# 0.10 % (point: the lifted colour's Y is 0.999 of its luminance), 0.20 %
# (spot, inside its falloff band at 64 spp), 0.02 % (directional). The model
# scaled by 2 and seen from twice as far gives the same image (a point
# light's candela grow by the square of the scale). Bad lights exit 2 naming
# the node or light and write nothing; a `range` is warned about by name.
source "$(dirname "$0")/lib_cli.sh"
python3 "$ROOT/tests/gltf_lights.py" gen "$ROOT" "$T" || { echo "FAIL: gltf_lights.py"; exit 1; }
scene() { # kind, scale -> a scene looking down at the floor from 6 x scale
    printf 'image 64 64\ncamera position 0 %s 0 direction 0 -1 0 up 0 0 1 fov 60\n' \
        "$(awk -v s="$2" 'BEGIN { print 6 * s }')"
    printf 'spectrum equal equal\nmaterial floor reflect equal 0.5\n'
    printf 'mesh %s.gltf material floor scale %s\n' "$1" "$2"
}
for kind in point spot directional; do
    scene $kind 1 > "$T/$kind.scene"
    for backend in cpu opencl; do
        "$BIN" render "$T/$kind.scene" --spp 64 --backend $backend -o "$T/$kind.exr" 2> "$T/err"
        check "$backend $kind: renders ($(tail -1 "$T/err"))" [ -s "$T/$kind.exr" ]
        check "$backend $kind: one light made" grep -qF "$kind.gltf: 1 light (KHR_lights_punctual)" "$T/err"
        worst=$(python3 "$ROOT/tests/gltf_lights.py" check $kind "$T/$kind.exr" 2> "$T/rings")
        echo "$backend $kind: worst ring $worst of the peak; $(cat "$T/rings")"
        check "$backend $kind: every ring within 1% of the peak of the closed form ($worst)" \
          num "$worst" "<" 0.01
        rm -f "$T/$kind.exr"
    done
done
scene point 2 > "$T/scaled.scene"
"$BIN" render "$T/scaled.scene" --spp 64 --backend cpu -o "$T/scaled.exr" 2> "$T/err"
worst=$(python3 "$ROOT/tests/gltf_lights.py" check point "$T/scaled.exr" 2> /dev/null)
check "scaled by 2, seen from twice as far: the same image ($worst)" num "$worst" "<" 0.01

# bad lights: exit 2, the node or light named, nothing written
bad_light() { # file, what the message must say
    scene "$1" 1 > "$T/bad.scene"
    msg=$("$BIN" render "$T/bad.scene" --spp 1 -o "$T/bad.png" 2>&1); rc=$?
    check "$1: exit 2 (got $rc: $msg)" [ "$rc" -eq 2 ]
    check "$1: names the file and says '$2' (got: $msg)" grep -qF -- "$1.gltf: $2" <<< "$msg"
    check "$1: nothing written" [ ! -e "$T/bad.png" ]
}
bad_light bad_index "node 2 ('lamp'): KHR_lights_punctual light 3 is out of range (the file defines 1 light)"
bad_light bad_type "KHR_lights_punctual light 0 ('lamp') of node 2: type 'area' (point, spot or directional)"
bad_light bad_cone "KHR_lights_punctual light 0 ('lamp') of node 2: cone angles inner 0.6, outer 0.5 radians"
bad_light bad_colour "KHR_lights_punctual light 0 ('lamp') of node 2: \`color\` must be three numbers"
scene range 1 > "$T/range.scene"
msg=$("$BIN" render "$T/range.scene" --spp 1 --backend cpu -o "$T/range.png" 2>&1); rc=$?
check "a light's range: renders (rc $rc)" [ "$rc" -eq 0 ]
check "a light's range: warned by name ($msg)" grep -qF "glTF light ranges (KHR_lights_punctual" <<< "$msg"
finish
