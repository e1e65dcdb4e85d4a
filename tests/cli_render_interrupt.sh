#!/usr/bin/env bash
# Ctrl-C on the OpenCL backend: inside a pass it stops at the next batch
# boundary (SPECMIP_TEST_PAUSE holds the program there, host/util/interrupt.h);
# during a program build it is acted on right after the build; a render left
# alone reports progress per batch; and with no hook at all, a single large
# pass is interrupted well within the bound below.
source "$(dirname "$0")/lib_cli.sh"

BOUND=5 # generous: the machine is shared (the latency is printed on stdout)
is_old() { [ "$(cat "$1")" = old ]; }
in_time() { awk -v l="$lat" -v b="$BOUND" 'BEGIN { exit !(l < b) }'; }
said() { grep -q "$1" "$T/err" || { echo "  stderr: $(tr '\r' '\n' < "$T/err" | tail -3)"; false; }; }

# signalled PAUSE WAITFOR ARGS...: renders ARGS (SPECMIP_TEST_PAUSE=PAUSE if
# not empty) and sends SIGINT once stderr matches WAITFOR. Sets rc and lat
# (seconds from the signal to the exit).
signalled() {
    local pause=$1 waitfor=$2 i t0
    shift 2
    : > "$T/err"
    SPECMIP_TEST_PAUSE=$pause "$BIN" render "$@" > /dev/null 2> "$T/err" &
    local pid=$!
    for ((i = 0; i < 1200; i++)); do
        grep -q "$waitfor" "$T/err" && break
        kill -0 $pid 2> /dev/null || break
        sleep 0.1
    done
    t0=$(date +%s.%N)
    kill -INT $pid 2> /dev/null
    wait $pid
    rc=$?
    lat=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }')
    echo "  ${pause:-no hook}: exit $rc after $lat s"
}

# 1024x768 at 1 spp per pass is three batches of at most 2^18 paths a pass.
R=(--width 1024 --height 768 --spp 2 --quiet)

# 1. Progress inside a pass: a line per batch, not only per pass.
"$BIN" render "${R[@]}" --spp 1 --progress -o "$T/p.exr" 2> "$T/err"
check "progress: exit 0" test $? -eq 0
check "progress: a third of the pass" said "pass 0/1   33%"
check "progress: two thirds of the pass" said "pass 0/1   67%"
check "progress: the pass done" said "pass 1/1  100%"

# 2. Inside the first pass: it stops after its first batch, nothing written.
echo old > "$T/o.exr"
signalled pass "test pause at pass" "${R[@]}" -o "$T/o.exr"
check "first pass: exit 130" test $rc -eq 130
check "first pass: within $BOUND s" in_time
check "first pass: says nothing was written" said "interrupted in the first pass.*no image written"
check "first pass: existing output untouched" is_old "$T/o.exr"

# 3. Inside the second pass (the third batch boundary): the first pass's image.
"$BIN" render "${R[@]}" --spp 1 -o "$T/one.exr"
signalled pass:3 "test pause at pass" "${R[@]}" -o "$T/o.exr"
check "second pass: exit 130" test $rc -eq 130
check "second pass: within $BOUND s" in_time
check "second pass: the first pass's image" same_pixels "$T/one.exr" "$T/o.exr"

# 4. During the program build, which cannot be interrupted: acted on after it.
echo old > "$T/o.exr"
signalled build "test pause at build" "${R[@]}" -o "$T/o.exr"
check "build: exit 130" test $rc -eq 130
check "build: says so" said "interrupted while building the OpenCL programs.*nothing rendered"
check "build: existing output untouched" is_old "$T/o.exr"

# 5. No hook: a 1-spp 2048x2048 render (one pass of 16 batches) interrupted
#    once its first batch is done.
signalled "" "pass 0/1 " --width 2048 --height 2048 --spp 1 --progress -o "$T/o.exr"
check "large pass: exit 130" test $rc -eq 130
check "large pass: within $BOUND s" in_time
check "large pass: existing output untouched" is_old "$T/o.exr"

finish
