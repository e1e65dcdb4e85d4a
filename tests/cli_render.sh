#!/bin/bash
# specmip render end to end: no arguments writes the default images; outputs
# that cannot be written are refused before rendering; bad scenes exit 2 naming
# file:line; SIGINT writes the image so far and exits 130; the same seed gives
# the same image; the CPU reference backend renders too.
# usage: bash tests/cli_render.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

# 1. No arguments: the default scene into specmip.png and specmip.exr in the
#    current directory (at a reduced spp through nothing but the defaults would
#    take ~15 s here; the full default is what README's first command runs).
(cd "$T" && "$BIN" render --quiet) ; rc=$?
[ $rc -eq 0 ] && ok || bad "render with no arguments exited $rc"
for f in specmip.png specmip.exr; do
  [ -s "$T/$f" ] && ok || bad "default output $f missing"
done
# the PNG is a picture, not noise: the red wall is red, the green wall green
python3 - "$T/specmip.exr" <<'PY' && ok || bad "default image content"
import subprocess, sys
# oiiotool prints per-channel stats of a crop: left wall vs right wall
def mean(crop):
    out = subprocess.run(["oiiotool", sys.argv[1], "--cut", crop, "--printstats"],
                         capture_output=True, text=True).stdout
    for line in out.splitlines():
        if "Stats Avg" in line:
            return [float(v) for v in line.split(":")[1].split()[:3]]
    raise SystemExit("no stats")
left, right = mean("20x100+20+80"), mean("20x100+216+80")
assert left[0] > 1.5 * left[1] and left[0] > 1.5 * left[2], left     # red wall
assert right[1] > 1.5 * right[0] and right[1] > 1.5 * right[2], right  # green wall
PY

# 2. Outputs checked before rendering
"$BIN" render --spp 1 -o "$T/nodir/x.png" 2>"$T/err"; rc=$?
[ $rc -eq 2 ] && grep -q "nodir" "$T/err" && ok || bad "missing output dir: rc $rc $(cat "$T/err")"
"$BIN" render --spp 1 -o "$T/x.bmpx" 2>"$T/err"; rc=$?
[ $rc -eq 2 ] && ok || bad "unknown extension: rc $rc"

# 3. Bad scenes: exit 2 with file:line
for f in "$ROOT"/tests/bad-inputs/*.scene "$ROOT"/tests/bad-inputs/*.ml.txt; do
  timeout 20 "$BIN" render "$f" --spp 1 -o "$T/bad.png" 2>"$T/err" >/dev/null; rc=$?
  name=$(basename "$f")
  if [ $rc -eq 2 ] && grep -q "$name" "$T/err"; then ok; else bad "$name: rc $rc: $(head -c 300 "$T/err")"; fi
  [ ! -e "$T/bad.png" ] && ok || { bad "$name left an output"; rm -f "$T/bad.png"; }
done
"$BIN" render "$T/does-not-exist.scene" -o "$T/x.png" 2>/dev/null; rc=$?
[ $rc -eq 2 ] && ok || bad "missing scene file: rc $rc"
"$BIN" render --mode nonsense 2>/dev/null; [ $? -eq 2 ] && ok || bad "bad mode accepted"
"$BIN" render --spp 0 2>/dev/null; [ $? -eq 2 ] && ok || bad "spp 0 accepted"

# 4. Same seed twice: bit-identical EXR pixels; another seed differs
for s in a b; do
  "$BIN" render --spp 2 --width 48 --height 48 --seed 7 -o "$T/$s.exr" --quiet || bad "seed 7 render $s"
done
"$BIN" render --spp 2 --width 48 --height 48 --seed 8 -o "$T/c.exr" --quiet || bad "seed 8 render"
same_pixels "$T/a.exr" "$T/b.exr" && ok || bad "same seed differs"
other_pixels "$T/a.exr" "$T/c.exr" && ok || bad "different seeds gave the same image (or an image is missing)"

# 5. SIGINT: the current pass ends, the image so far is written, exit 130;
#    an existing output is replaced only by a complete file.
echo "old" > "$T/int.png"
"$BIN" render --spp 100000 --width 64 --height 64 -o "$T/int.png" --progress 2>"$T/int.err" &
pid=$!
rendering $pid "$T/int.err" && ok || bad "SIGINT: the render never got under way"
kill -INT $pid
wait $pid; rc=$?
[ $rc -eq 130 ] && ok || bad "SIGINT exit code $rc"
head -c 4 "$T/int.png" | grep -q "PNG" && ok || bad "interrupted render did not write a PNG"
grep -q "interrupted after [1-9][0-9]* of 100000 samples" "$T/int.err" && ok ||
  bad "SIGINT: no message $(tr '\r' '\n' < "$T/int.err" | tail -n 2)"

# 6. The CPU reference backend and every mode render: a finite image that is
#    not black, the mode the stats report is the one asked for, and (but for
#    mlc, which on a scene without spikes is ml) each mode's image differs
#    from ref's, so the mode was used.
for m in truth ref ml mlc hero rgb; do
  "$BIN" render --backend cpu --mode $m --spp 1 --width 16 --height 16 -o "$T/cpu_$m.exr" --quiet \
    --json > "$T/cpu_$m.json" && [ -s "$T/cpu_$m.exr" ] && ok || bad "cpu backend mode $m"
  [ "$(jq -r .mode "$T/cpu_$m.json")" = $m ] && ok || bad "cpu backend mode $m: stats say $(jq .mode "$T/cpu_$m.json")"
  oiiotool "$T/cpu_$m.exr" --printstats > "$T/cpu_$m.stats" 2>&1
  grep -q "NanCount: 0 0 0" "$T/cpu_$m.stats" && awk '/Stats Avg/ { n++; if (!($3 > 0 && $4 > 0 && $5 > 0)) dark = 1 }
    END { exit dark || n != 1 }' "$T/cpu_$m.stats" && ok || bad "cpu backend mode $m: $(cat "$T/cpu_$m.stats")"
done
for m in truth ml hero rgb; do
  other_pixels "$T/cpu_ref.exr" "$T/cpu_$m.exr" && ok || bad "mode $m renders ref's image (or an image is missing)"
done

# 7. --stats --json: one JSON object with the figures the benchmarks read
"$BIN" render --spp 1 --width 32 --height 32 -o "$T/s.png" --json --quiet > "$T/s.json" ||
  bad "--json render exited $?"
python3 - "$T/s.json" <<'PY' && ok || bad "stats json"
import json, sys
d = json.load(open(sys.argv[1]))
for k in ("wall_s", "trace_s", "shade_s", "paths_per_s", "levels", "devices", "truncated", "nonfinite"):
    assert k in d, k
assert d["paths"] == 32 * 32, d["paths"]
assert sum(l["paths"] for l in d["levels"]) == d["paths"]
b = d["bvh"]
assert b["triangles"] == 32, b              # the built-in box
assert b["nodes"] == 2 * b["leaves"] - 1, b  # every interior node has two children
assert b["leaves"] >= b["triangles"] / 2, b  # leaves hold at most 2 triangles
assert b["sah_cost"] >= 1.0, b               # at least the root's own box test
assert b["threads"] >= 1, b
assert d["peak_rss_bytes"] > 1 << 20, d["peak_rss_bytes"]
PY

finish
