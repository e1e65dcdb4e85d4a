#!/bin/bash
# Devices and numbers, through the CLI on the OpenCL device: an unknown
# --device lists the available ones; a kernel that does not compile shows the
# compiler's log and leaves no output; an image of more paths a pass than
# one batch renders (the refusal of what still does not fit a device is
# test_robust_resources'); NaN/Inf samples (an emission that overflows
# float in the device tables) are counted in --stats and kept out of the film
# with the kernels' real build options; the bundled scenes give none; SIGTERM
# writes the image so far. Skipped in the sanitizer build (no OpenCL there).
# usage: bash tests/cli_robust_device.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"
if grep -qa __asan_init "$BIN"; then
  skip "sanitizer build (PoCL and the ICD loader are not instrumented)"
fi
small=(--spp 4 --width 8 --height 8 --quiet)

# 1. Unknown device: exit 2, the message lists device 0 by its name.
dev0=$("$BIN" devices | sed -n 's/^ *device 0: //p' | head -n 1)
"$BIN" render --device 99 "${small[@]}" -o "$T/d.png" 2>"$T/err"; rc=$?
[ $rc -eq 2 ] && grep -q "99" "$T/err" && grep -qF "0: $dev0" "$T/err" && ok \
  || bad "unknown device: rc $rc: $(cat "$T/err")"

# 2. A kernel that does not compile: a copy of the data root whose shade.cl
#    ends in a line that is not OpenCL C; exit 1 and the log names it.
mkdir -p "$T/data"
for d in spectra scenes include; do ln -s "$SPECMIP_DATA/$d" "$T/data/$d"; done
cp -r "$SPECMIP_DATA/kernels" "$T/data/kernels"
echo "spm_robust_broken_kernel here;" >> "$T/data/kernels/shade.cl"
SPECMIP_DATA="$T/data" "$BIN" render "${small[@]}" -o "$T/k.png" 2>"$T/err"; rc=$?
[ $rc -eq 1 ] && grep -q "build log" "$T/err" && grep -q "spm_robust_broken_kernel" "$T/err" && ok \
  || bad "kernel build failure: rc $rc: $(head -c 600 "$T/err")"
[ ! -e "$T/k.png" ] && ok || bad "a failed build left an output"

# 3. A large image renders: a pass is traced and shaded in batches of at
#    most 2^18 paths (cl_resources.h), so the device buffers do not grow with
#    the image (before batching, 4096 x 4096 was refused for 8 GB of path
#    records in one buffer). 16384 x 32 at 1 spp is 512K paths, two batches,
#    and quick; test_cl_batch shows the image does not depend on the batches,
#    test_robust_resources what is still refused (a scene or a batch too
#    large for a device), which a device here cannot show without a
#    multi-gigabyte scene.
"$BIN" render --spp 1 --width 16384 --height 32 -o "$T/wide.exr" --json --quiet \
  > "$T/wide.json" 2>"$T/err"; rc=$?
[ $rc -eq 0 ] && [ -s "$T/wide.exr" ] && ok || bad "16384x32: rc $rc: $(head -c 300 "$T/err")"
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["paths"] == 16384 * 32 and d["nonfinite"] == 0, d' \
  "$T/wide.json" 2>/dev/null && ok || bad "16384x32: paths or non-finite samples: $(head -c 300 "$T/wide.json")"

# 4. Non-finite samples: a light of luminance 2e38 (float holds it, so the
#    scene loads) 5 cm from a wall, next to an ordinary light; the camera sits
#    between light and wall, so it sees wall points whose one-sample light
#    estimate (area / d^2 large) overflows float. The Inf samples are counted
#    and left out, so the film stays finite and the ordinary light still
#    shows. Every mode's kernel (they are built with the options a render
#    uses), and the CPU reference.
cat > "$T/hot.scene" <<'SCENE'
image 8 8
camera position -1 0.5 0.03 direction 0 0 1 fov 90
spectrum flat equal
material hot emit flat 2e38
material lamp emit flat 1
material wall reflect flat 0.5
quad wall -5 -1 0.05  5 -1 0.05  5 4 0.05  -5 4 0.05
tri hot -1.5 0 0  -0.5 0 0  -1 1.5 0
tri lamp 0.5 0 0  1.5 0 0  1 1.5 0
SCENE
for m in truth ref ml mlc hero rgb cpu; do
  if [ $m = cpu ]; then args=(--backend cpu); else args=(--mode $m); fi
  "$BIN" render "$T/hot.scene" "${args[@]}" --spp 8 -o "$T/hot_$m.exr" --json --quiet \
    > "$T/hot_$m.json" 2>"$T/err" || { bad "hot scene, $m: $(head -c 300 "$T/err")"; continue; }
  python3 - "$T/hot_$m.json" "$T/hot_$m.exr" <<'PY' && ok || bad "nonfinite guard, $m"
import json, subprocess, sys
d = json.load(open(sys.argv[1]))
assert 0 < d["nonfinite"] < d["paths"], d["nonfinite"]
out = subprocess.run(["oiiotool", sys.argv[2], "--printstats"], capture_output=True, text=True).stdout
stats = {l.split(":")[0].strip(): l.split(":")[1].split() for l in out.splitlines() if ":" in l}
assert stats["Stats NanCount"] == ["0"] * 3 and stats["Stats InfCount"] == ["0"] * 3, stats
assert all(float(v) > 0 for v in stats["Stats Avg"][:3]), stats["Stats Avg"]
PY
done

# 5. No non-finite sample in the bundled scenes: every scene in the default
#    mode, every mode on the spiky scenes (narrow lines, large level jumps).
#    (A 4096 spp run of every scene and mode at 8x8 also gave zero.)
check_zero() {
  "$BIN" render "$1" --mode "$2" --spp 64 --width 8 --height 8 -o "$T/z.exr" --json --quiet \
    > "$T/z.json" 2>"$T/err"; rc=$?
  [ $rc -eq 0 ] || { bad "$(basename "$1") $2: exit $rc: $(head -c 300 "$T/err")"; return; }
  python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert d["nonfinite"] == 0 and d["paths"] == 4096, d' \
    "$T/z.json" 2>/dev/null && ok || bad "$(basename "$1") $2: non-finite samples"
}
for s in "$ROOT"/scenes/*.scene; do check_zero "$s" ml; done
for s in "$ROOT"/scenes/cornell_spiky.scene "$ROOT"/scenes/narrowline.scene; do
  for m in truth ref mlc hero rgb; do check_zero "$s" $m; done
done

# 6. SIGTERM on the OpenCL backend: the image so far is written, exit 130.
echo "old" > "$T/term.png"
"$BIN" render --spp 1000000 --width 32 --height 32 -o "$T/term.png" --progress 2>"$T/term.err" & pid=$!
rendering $pid "$T/term.err" && ok || bad "SIGTERM: the render never finished a pass"
kill -TERM $pid; wait $pid; rc=$?
[ $rc -eq 130 ] && ok || bad "SIGTERM exit code $rc"
head -c 4 "$T/term.png" | grep -q PNG && ok || bad "SIGTERM: no PNG written"

finish
