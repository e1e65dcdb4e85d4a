#!/usr/bin/env bash
# Ctrl-C / SIGTERM at each moment of a render on the CPU reference (no OpenCL,
# so the sanitizer build runs it too): while the scene, a CSV spectrum, the BVH
# and the pretests are being prepared, inside a pass, and while the images are
# written, and while a checkpoint is written (--checkpoint); a second signal. The test hook SPECMIP_TEST_PAUSE (host/util/interrupt.h)
# holds the program at a named stage until the signal arrives. Each time: exit
# 130 well within the bound below, the message names the moment, existing
# outputs are replaced by complete images only, and no temporary file is left.
source "$(dirname "$0")/lib_cli.sh"

# Generous: the machine is shared. The latency measured here is reported on
# stdout; on a quiet machine it is a few tens of milliseconds.
BOUND=5
no_temps() { [ -z "$(find "$@" -name '*spmtmp*' -o -name '.specmip-probe*')" ]; }
is_old() { [ "$(cat "$1")" = old ]; }
is_png() { head -c 4 "$1" | grep -q PNG; }

# paused PAUSE NSIG SIG ARGS...: renders ARGS with SPECMIP_TEST_PAUSE=PAUSE,
# sending SIG each of the first NSIG times the program says it has paused.
# Sets rc (its exit status) and lat (seconds from the last signal to its exit).
paused() {
    local pause=$1 nsig=$2 sig=$3 k i t0
    shift 3
    : > "$T/err"
    SPECMIP_TEST_PAUSE=$pause "$BIN" render "$@" > "$T/out" 2> "$T/err" &
    local pid=$!
    t0=$(date +%s.%N)
    for ((k = 1; k <= nsig; k++)); do
        for ((i = 0; i < 600; i++)); do
            [ "$(grep -c 'test pause at' "$T/err")" -ge "$k" ] && break
            kill -0 $pid 2> /dev/null || break
            sleep 0.1
        done
        t0=$(date +%s.%N)
        kill -"$sig" $pid 2> /dev/null
    done
    wait $pid
    rc=$?
    lat=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }')
    echo "  $pause ($nsig x SIG$sig): exit $rc after $lat s"
}
in_time() { awk -v l="$lat" -v b="$BOUND" 'BEGIN { exit !(l < b) }'; }
said() { grep -q "$1" "$T/err" || { echo "  stderr: $(tr '\r' '\n' < "$T/err" | tail -3)"; false; }; }

SMALL=(--backend cpu --spp 2 --width 32 --height 32 --quiet)
# 256x512 at 1 spp per pass: two CPU batches (2^16 paths) a pass, two passes.
TWO=(--backend cpu --spp 2 --width 256 --height 512 --quiet)

# 1. Before anything is rendered: nothing written, existing output untouched.
for stage in load:3 csv:2 bvh:2 pretest:2; do
    echo old > "$T/o.png"
    sig=INT; [ "$stage" = csv:2 ] && sig=TERM
    paused "$stage" 1 $sig "${SMALL[@]}" -o "$T/o.png"
    case $stage in
    load*) what="interrupted while loading .*cornell.scene (line 4)" ;; # line 3 read
    csv*) what="interrupted while loading .*\.csv (line 2)" ;;
    bvh*) what="interrupted while building the BVH" ;;
    pretest*) what="interrupted during the pretests (1 of [0-9]* colours done)" ;;
    esac
    check "$stage: exit 130" test $rc -eq 130
    check "$stage: within $BOUND s" in_time
    check "$stage: says where" said "$what"
    check "$stage: says nothing was written" said "nothing rendered, no image written"
    check "$stage: existing output untouched" is_old "$T/o.png"
    check "$stage: no temporary file" no_temps "$T"
done

# 1b. While the project's PLY reader reads a mesh, in process (it asks every
#     65536 items, and first at the vertex element's first).
python3 "$ROOT/tools/gen_meshes.py" --scale sphere 5000 "$T/s.ply" "$T/s.scene" > /dev/null ||
  { echo "FAIL: gen_meshes.py --scale"; exit 1; }
echo old > "$T/o.png"
paused ply 1 INT "$T/s.scene" "${SMALL[@]}" -o "$T/o.png"
check "ply: exit 130" test $rc -eq 130
check "ply: within $BOUND s" in_time
check "ply: says where" said "interrupted while loading .*s.ply (element vertex, item 1)"
check "ply: says nothing was written" said "nothing rendered, no image written"
check "ply: existing output untouched" is_old "$T/o.png"

# 1c. Within one long list: a strip mesh of 1000 vertices whose one strip
#     lists 200000 indices (the reader asks every 65536 values of a list too:
#     its third pause is the one at value 65537, after the vertex element's
#     and the strip element's first item).
python3 - "$T/strip.ply" <<'PY' || { echo "FAIL: strip.ply"; exit 1; }
import struct, sys
w, n = 500, 200000  # two rows of w vertices, the strip zigzagging along them again and again
with open(sys.argv[1], 'wb') as f:
    f.write(b'ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n'
            b'property float y\nproperty float z\nelement tristrips 1\n'
            b'property list int int vertex_indices\nend_header\n' % (2 * w))
    f.write(b''.join(struct.pack('<3f', c / w - 0.5, r * 0.1, 0.0) for r in (0, 1) for c in range(w)))
    f.write(struct.pack('<%di' % (n + 1), n, *[(k // 2) % w + w * (k % 2) for k in range(n)]))
PY
sed 's|s.ply|strip.ply|' "$T/s.scene" > "$T/strip.scene"
echo old > "$T/o.png"
paused ply:3 1 INT "$T/strip.scene" "${SMALL[@]}" -o "$T/o.png"
check "ply list: exit 130" test $rc -eq 130
check "ply list: within $BOUND s" in_time
check "ply list: says where" said "interrupted while loading .*strip.ply (element tristrips, item 1, value 65537 of its list)"
check "ply list: says nothing was written" said "nothing rendered, no image written"
check "ply list: existing output untouched" is_old "$T/o.png"

# 2. Inside the first pass (after its first batch): the pass ends there,
#    so nothing is rendered and nothing written.
echo old > "$T/o.png"
paused pass 1 INT "${TWO[@]}" -o "$T/o.png"
check "first pass: exit 130" test $rc -eq 130
check "first pass: within $BOUND s" in_time
check "first pass: says nothing was written" said "interrupted in the first pass.*no image written"
check "first pass: existing output untouched" is_old "$T/o.png"

# 3. Inside the second pass: the image of the first pass, as a 1-spp render
#    gives it (the half-done second pass is dropped), in both outputs.
"$BIN" render "${TWO[@]}" --spp 1 -o "$T/one.exr"
echo old > "$T/o.png"
echo old > "$T/o.exr"
paused pass:2 1 INT "${TWO[@]}" -o "$T/o.png" -o "$T/o.exr"
check "second pass: exit 130" test $rc -eq 130
check "second pass: within $BOUND s" in_time
check "second pass: says so" said "interrupted after 1 of 2 samples per pixel; image written"
check "second pass: the first pass's image" same_pixels "$T/one.exr" "$T/o.exr"
check "second pass: PNG written" is_png "$T/o.png"
check "second pass: no temporary file" no_temps "$T"

# 4. A second signal, while the first is being acted on (the image of the
#    first pass is being written): exit at once, old outputs untouched, the
#    temporary file of the write in progress removed.
echo old > "$T/o.png"
echo old > "$T/o.exr"
paused pass:2,write 2 INT "${TWO[@]}" -o "$T/o.png" -o "$T/o.exr"
check "second signal: exit 130" test $rc -eq 130
check "second signal: within $BOUND s" in_time
check "second signal: says so" said "interrupted again"
check "second signal: first output untouched" is_old "$T/o.png"
check "second signal: second output untouched" is_old "$T/o.exr"
check "second signal: no temporary file" no_temps "$T"

# ... during the second output's write: the first is complete, the second old.
echo old > "$T/o.png"
echo old > "$T/o.exr"
paused pass:2,write:2 2 TERM "${TWO[@]}" -o "$T/o.exr" -o "$T/o.png"
check "second signal, second write: exit 130" test $rc -eq 130
check "second signal, second write: first output complete" same_pixels "$T/one.exr" "$T/o.exr"
check "second signal, second write: second untouched" is_old "$T/o.png"
check "second signal, second write: no temporary file" no_temps "$T"

# 5. One signal while the finished render is written: every output is
#    written complete (an image write is not interrupted), then exit 130.
"$BIN" render "${SMALL[@]}" -o "$T/full.exr"
echo old > "$T/o.png"
echo old > "$T/o.exr"
paused write 1 INT "${SMALL[@]}" -o "$T/o.exr" -o "$T/o.png"
check "signal during a write: exit 130" test $rc -eq 130
check "signal during a write: says so" said "interrupted once the render was done; the complete image was written"
check "signal during a write: first output complete" same_pixels "$T/full.exr" "$T/o.exr"
check "signal during a write: second output written" is_png "$T/o.png"
check "signal during a write: no temporary file" no_temps "$T"

# 7. Checkpoints (--checkpoint, docs/RENDERING.md): the film is written first,
#    then the images, each to a temporary file renamed over the last one.
#    64x64 at 16 spp a pass, a checkpoint after every pass or so; the test
#    pause "film" holds the second checkpoint's film write (the first is done).
CK=(--backend cpu --width 64 --height 64 --spp 4096 --checkpoint 0.1 --quiet)
film_samples() { grep -a -m1 '^samples=' "$1" | cut -d= -f2; }
exr_spp() { oiiotool --info -v "$1" 2> /dev/null | sed -n 's/^ *samplesPerPixel: //p'; }
resumes() { "$BIN" render "${CK[@]}" --spp $(($(film_samples "$1.film") + 16)) --resume "$1" -o "$T/res.exr"; }
mkdir "$T/ck"
# a) Killed outright while the second checkpoint's film is written: the first
#    checkpoint's film and images are there as they were, and resume.
: > "$T/err"
SPECMIP_TEST_PAUSE=film:2 "$BIN" render "${CK[@]}" -o "$T/ck/c.exr" -o "$T/ck/c.png" 2> "$T/err" &
pid=$!
for ((i = 0; i < 600; i++)); do
    grep -q "test pause at film" "$T/err" && break
    sleep 0.1
done
cp "$T/ck/c.exr" "$T/first.exr" && cp "$T/ck/c.exr.film" "$T/first.film" && cp "$T/ck/c.png" "$T/first.png"
kill -KILL $pid
wait $pid 2> /dev/null
check "checkpoint killed: paused in the second film write" said "test pause at film"
check "checkpoint killed: the first checkpoint's film untouched" cmp -s "$T/first.film" "$T/ck/c.exr.film"
check "checkpoint killed: its EXR untouched" cmp -s "$T/first.exr" "$T/ck/c.exr"
check "checkpoint killed: its PNG untouched" cmp -s "$T/first.png" "$T/ck/c.png"
check "checkpoint killed: the film resumes" resumes "$T/ck/c.exr"
rm -rf "$T/ck" && mkdir "$T/ck"
# b) Ctrl-C during the second checkpoint's film write: that checkpoint is
#    completed, then the passes done are written; film and EXR agree.
paused film:2 1 INT "${CK[@]}" -o "$T/ck/c.exr" -o "$T/ck/c.png"
check "checkpoint, Ctrl-C: exit 130" test $rc -eq 130
check "checkpoint, Ctrl-C: the passes done written" said "interrupted after [0-9]* of 4096 samples per pixel; image written"
check "checkpoint, Ctrl-C: film and EXR agree" test "$(film_samples "$T/ck/c.exr.film")" = "$(exr_spp "$T/ck/c.exr")"
check "checkpoint, Ctrl-C: no temporary file" no_temps "$T"
check "checkpoint, Ctrl-C: the film resumes" resumes "$T/ck/c.exr"
rm -rf "$T/ck" && mkdir "$T/ck"
# c) A second signal while that checkpoint's EXR is written (after its film):
#    exit at once; the EXR is the first checkpoint's, no temporary file, and
#    it resumes from the film written just before.
: > "$T/err"
SPECMIP_TEST_PAUSE=film:2,write:2 "$BIN" render "${CK[@]}" -o "$T/ck/c.exr" 2> "$T/err" &
pid=$!
for ((i = 0; i < 600; i++)); do
    grep -q "test pause at film" "$T/err" && break
    sleep 0.1
done
cp "$T/ck/c.exr" "$T/first.exr"
kill -INT $pid
for ((i = 0; i < 600; i++)); do
    grep -q "test pause at write" "$T/err" && break
    sleep 0.1
done
kill -TERM $pid
wait $pid
rc=$?
check "checkpoint, second signal: exit 130" test $rc -eq 130
check "checkpoint, second signal: says so" said "interrupted again"
check "checkpoint, second signal: the EXR is the first checkpoint's" cmp -s "$T/first.exr" "$T/ck/c.exr"
check "checkpoint, second signal: no temporary file" no_temps "$T"
check "checkpoint, second signal: the film is the second's" \
    num "$(film_samples "$T/ck/c.exr.film")" '>' "$(exr_spp "$T/ck/c.exr")"
check "checkpoint, second signal: the film resumes" resumes "$T/ck/c.exr"

# 6. Without the hook: the test pause does nothing unless asked for, and a
#    render left alone exits 0.
"$BIN" render "${SMALL[@]}" -o "$T/plain.exr"
check "no hook: exit 0" test $? -eq 0
check "no hook: same image" same_pixels "$T/full.exr" "$T/plain.exr"

finish
