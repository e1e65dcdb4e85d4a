#!/bin/bash
# Renders every bundled scene (scenes/*.scene) small into docs/gallery/NAME.png
# for README's gallery: mode ml, the scene's own aspect with its longer side
# SIZE pixels, SPP samples, seed 1. The PNGs are tone-mapped as `render` does.
# usage: tools/gallery.sh [SPECMIP] [SIZE] [SPP] [SCENE...]
#   (build/specmip, 128, 64, every scene; SCENE a name under scenes/, without .scene)
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$root/build/specmip}
size=${2:-128}
spp=${3:-64}
shift $(($# < 3 ? $# : 3))
[ -x "$bin" ] || { echo "gallery.sh: no binary at $bin" >&2; exit 2; }
out=$root/docs/gallery
mkdir -p "$out"
scenes=("$root"/scenes/*.scene)
if [ $# -gt 0 ]; then
    scenes=()
    for name in "$@"; do scenes+=("$root/scenes/$name.scene"); done
fi
for scene in "${scenes[@]}"; do
    [ -f "$scene" ] || { echo "gallery.sh: no scene $scene" >&2; exit 2; }
    name=$(basename "$scene" .scene)
    # the scene's image line (256 256 unless it says), scaled to SIZE on its longer side
    read -r w h < <(awk -v s="$size" '$1 == "image" { w = $2; h = $3 }
        END { if (!w) { w = 256; h = 256 }
              if (w >= h) printf "%d %d\n", s, (h * s / w < 1 ? 1 : h * s / w + 0.5)
              else printf "%d %d\n", (w * s / h < 1 ? 1 : w * s / h + 0.5), s }' "$scene")
    extra=()
    case $name in # a scene only light subpaths reach (a path tracer renders it black)
        prism_wall | ball_lens) extra=(--integrator light) ;;
        water_caustic | lamp_room | frosted_lamp) extra=(--integrator bdpt) ;; # caustics, a lamp behind frosted glass
    esac
    "$bin" render "$scene" --mode ml --width "$w" --height "$h" --spp "$spp" --seed 1 --quiet \
        ${extra[@]+"${extra[@]}"} -o "$out/$name.png"
    echo "gallery.sh: $name ${w}x$h" >&2
done
