#!/bin/bash
# Benchmark (not a test): the spectral methods side by side on one
# scene - shade-stage time and whole-render paths/s of each mode, and its bias
# against ref (same seed: same paths, ΔE00 of 5x5-blurred images). The goal is
# an mlc shade stage >= 1.3x faster than ml's on the spiky scene at equal or
# lower error against ref.
# usage: bench/methods.sh [path/to/specmip]   (default build/specmip)
# env:   SCENE (scenes/cornell_spiky.scene), SIZE (256), SPP (64),
#        REPEAT (3: each mode's best shade time and paths/s of REPEAT runs, as
#        other work on the machine only ever slows a run down),
#        MODES (default every mode, `specmip modes`), OUT (a temporary directory)
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$ROOT/build/specmip}
export SPECMIP_DATA=${SPECMIP_DATA:-$ROOT}
SCENE=${SCENE:-$ROOT/scenes/cornell_spiky.scene}
SIZE=${SIZE:-256}
SPP=${SPP:-64}
REPEAT=${REPEAT:-3}
OUT=${OUT:-$(mktemp -d)}
[ -x "$BIN" ] || { echo "bench/methods.sh: no specmip binary at $BIN" >&2; exit 2; }
MODES=${MODES:-$("$BIN" modes | cut -f1 | tr '\n' ' ')}
mkdir -p "$OUT"

# ref first: the others are compared with its image
for m in ref $(printf '%s\n' $MODES | grep -vx ref); do
    for r in $(seq "$REPEAT"); do
        "$BIN" render "$SCENE" --mode "$m" --spp "$SPP" --width "$SIZE" --height "$SIZE" \
            --quiet --json -o "$OUT/$m.exr" >"$OUT/$m.$r.json"
    done
    python3 - "$OUT" "$m" "$REPEAT" <<'PY'
import json, sys
out, m, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
runs = [json.load(open(f"{out}/{m}.{r}.json")) for r in range(1, n + 1)]
best = dict(runs[0])
best["shade_s"] = min(r["shade_s"] for r in runs)
best["paths_per_s"] = max(r["paths_per_s"] for r in runs)
json.dump(best, open(f"{out}/{m}.json", "w"))
PY
    "$BIN" compare "$OUT/ref.exr" "$OUT/$m.exr" --json >"$OUT/$m.cmp.json"
done

echo "scene $(basename "$SCENE"), ${SIZE}x${SIZE}, $SPP spp, best of $REPEAT runs; bias = ΔE00 vs ref (blur 5, same seed)"
python3 - "$OUT" $MODES <<'PY'
import json, sys
out, modes = sys.argv[1], sys.argv[2:]
st = {m: json.load(open(f"{out}/{m}.json")) for m in modes}
cmp = {m: json.load(open(f"{out}/{m}.cmp.json")) for m in modes}
ml_shade = st["ml"]["shade_s"] if "ml" in st else None
print(f"{'mode':6} {'shade_s':>9} {'vs ml':>6} {'Mpaths/s':>9} {'dE00 mean':>10} {'dE00 max':>9}  paths per level 0/1/2/3")
for m in modes:
    s, c = st[m], cmp[m]
    speed = f"{ml_shade / s['shade_s']:6.2f}" if ml_shade and s["shade_s"] > 0 else "     -"
    lv = "/".join(str(l["paths"]) for l in s["levels"]) if s["levels"] else "-"  # ml, mlc only
    print(f"{m:6} {s['shade_s']:9.4f} {speed} {s['paths_per_s'] * 1e-6:9.3f} {c['mean']:10.3f} {c['max']:9.3f}  {lv}")
if "ml" in st and "mlc" in st:
    sp = ml_shade / st["mlc"]["shade_s"]
    ok = sp >= 1.3 and cmp["mlc"]["mean"] <= cmp["ml"]["mean"]
    print(f"goal (mlc shade >= 1.3x ml's at equal or lower error vs ref): {sp:.2f}x, "
          f"dE00 mean mlc {cmp['mlc']['mean']:.3f} vs ml {cmp['ml']['mean']:.3f}: {'met' if ok else 'MISSED'}")
PY
echo "files in $OUT"
