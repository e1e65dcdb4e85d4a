#!/bin/bash
# Benchmark (not a test): one render across several OpenCL devices.
#  1. POCL_DEVICES="basic basic" (two single-threaded devices, one per core):
#     two devices against one, paths/s. Goal: >= 1.8x.
#  2. POCL_DEVICES="pthread basic" (a multi-threaded and a single-threaded
#     device): each alone, then both; the work shares against the speeds
#     measured alone and in the joint run, and the joint paths/s against the
#     faster device alone. Goal: not below it.
# Runs are interleaved (a, b, c, a, b, c, ...) so load from other work on the
# machine falls on every configuration alike; each reports its best of REPEAT
# runs (other work only ever slows a run down) and the spread (worst/best).
# A device's idle time (wall - busy) is what the split's imbalance at the end
# cost it. Paths/s is the render loop's (paths / wall time of the passes): program
# builds are left out, the first pass's kernel compilation is in. Each line
# also shows the cores the render got (process CPU s / wall s) and the paths
# per CPU second: on a busy machine the first falls short of the devices'
# thread count, while the second shows whether splitting cost any work.
# usage: bench/multidevice.sh [path/to/specmip]   (default build/specmip)
# env:   SCENE (the default Cornell box), SIZE (256), SPP (64), REPEAT (3),
#        OUT (a temporary directory)
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$ROOT/build/specmip}
export SPECMIP_DATA=${SPECMIP_DATA:-$ROOT}
SIZE=${SIZE:-256}
SPP=${SPP:-64}
REPEAT=${REPEAT:-3}
OUT=${OUT:-$(mktemp -d)}
[ -x "$BIN" ] || { echo "bench/multidevice.sh: no specmip binary at $BIN" >&2; exit 2; }
mkdir -p "$OUT"
RENDER=(render ${SCENE:+"$SCENE"} --spp "$SPP" --width "$SIZE" --height "$SIZE" --quiet --json)

# The pthread device's index (PoCL need not list devices in POCL_DEVICES order).
pth=$(POCL_DEVICES="pthread basic" "$BIN" devices | grep -m1 'device [0-9]*: pthread' |
      sed 's/ *device \([0-9]*\):.*/\1/')
bas=$((1 - pth))
# name|POCL_DEVICES|--device
CONFIGS=("bb_one|basic basic|0" "bb_two|basic basic|all"
         "pb_pthread|pthread basic|$pth" "pb_basic|pthread basic|$bas" "pb_both|pthread basic|all")

echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
for r in $(seq "$REPEAT"); do
    for c in "${CONFIGS[@]}"; do
        IFS='|' read -r name devs dev <<< "$c"
        POCL_DEVICES=$devs "$BIN" "${RENDER[@]}" --device "$dev" -o "$OUT/$name.exr" \
            > "$OUT/$name.$r.json"
    done
done
echo "load after:  $(cut -d' ' -f1-3 /proc/loadavg)"

python3 - "$OUT" "$REPEAT" "$pth" <<'PY'
import json, sys
out, n, pth = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
def runs(name):
    return [json.load(open(f"{out}/{name}.{r}.json")) for r in range(1, n + 1)]
def best(name):
    rs = runs(name)
    b = max(rs, key=lambda j: j["paths_per_s"])
    worst = min(j["paths_per_s"] for j in rs)
    return b, worst / b["paths_per_s"]
def line(label, name):
    b, spread = best(name)
    print(f"  {label:<28} {b['paths_per_s'] / 1e6:7.3f} Mpaths/s  (wall {b['wall_s']:.2f} s, "
          f"worst run {spread:.2f} of best; {b['cpu_s'] / b['wall_s']:.2f} cores, "
          f"{b['paths'] / b['cpu_s'] / 1e6:.3f} Mpaths per CPU s)")
    return b

print(f"\n1. POCL_DEVICES='basic basic'  ({n} runs each, best)")
one = line("one device (--device 0)", "bb_one")
two = line("two devices (--device all)", "bb_two")
for d in two["devices"]:
    print(f"     {d['name'][:40]:<40} share {d['share']:.3f}  {d['paths_per_s'] / 1e6:.3f} Mpaths/s busy"
          f"  idle {two['wall_s'] - d['busy_s']:.3f} s")
print(f"  two / one = {two['paths_per_s'] / one['paths_per_s']:.2f}x   (goal >= 1.8x); "
      f"per CPU second {two['paths'] / two['cpu_s'] / (one['paths'] / one['cpu_s']):.2f}x")

print(f"\n2. POCL_DEVICES='pthread basic'")
p = line("pthread alone", "pb_pthread")
b = line("basic alone", "pb_basic")
both = line("both (--device all)", "pb_both")
alone = {"pthread": p["paths_per_s"], "basic": b["paths_per_s"]}
for d in both["devices"]:
    kind = "pthread" if "pthread" in d["name"] else "basic"
    print(f"     {d['name'][:40]:<40} share {d['share']:.3f}  "
          f"(speed share alone {alone[kind] / sum(alone.values()):.3f}, "
          f"in the joint run {d['paths_per_s'] / sum(x['paths_per_s'] for x in both['devices']):.3f})"
          f"  {d['passes']} passes, idle {both['wall_s'] - d['busy_s']:.3f} s")
print(f"  both / pthread alone = {both['paths_per_s'] / p['paths_per_s']:.2f}x   (goal >= 1.0x)")
PY
echo
echo "command: $0 $BIN   (SIZE=$SIZE SPP=$SPP REPEAT=$REPEAT${SCENE:+ SCENE=$SCENE})"
