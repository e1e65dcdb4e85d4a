#!/bin/bash
# specmip render --time and --checkpoint (docs/RENDERING.md): --time 3 on the
# default scene ends within its 3 s of rendering (start-up and writing are not
# counted, and the bound below is generous: speed is not what is tested) and
# records its samples per pixel; with --spp too the first limit ends it; a
# long render with --checkpoint writes its outputs and film again and again,
# each a valid image whenever it is read, and a film read mid-render resumes
# bit for bit to one render's image.
source "$(dirname "$0")/lib_cli.sh"
exr_attr() { oiiotool --info -v "$1" 2> /dev/null | sed -n "s/^ *$2: \"*\([^\"]*\)\"*$/\1/p"; }
film_samples() { grep -a -m1 '^samples=' "$1" | cut -d= -f2; }
said() { grep -q "$1" "$T/err" || { echo "  stderr: $(tail -3 "$T/err")"; false; }; }
not_grep() { ! grep -q "$1" "$2"; }

# 1. --time 3 on the default scene. The render loop may overrun the budget
#    by the pass in flight when the budget is spent (it is stopped at its next
#    batch) on a loaded machine: 2 s more is ample at 256x256, where a pass is
#    1 spp (~0.05 s on 2 cores). The whole process adds start-up and writing.
t0=$(date +%s.%N)
timeout 120 "$BIN" render --time 3 --json -o "$T/t.exr" > "$T/t.json" 2> "$T/err"
rc=$?
wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.3f", b - a }')
render_s=$(jnum "$T/t.json" .stages.render_s)
setup_s=$(jnum "$T/t.json" '.stages.load_s + .stages.bvh_s + .stages.tables_s + .stages.kernel_build_s')
spp=$(exr_attr "$T/t.exr" samplesPerPixel)
echo "  --time 3: render loop $render_s s, set-up $setup_s s, process $wall s, $spp spp"
check "--time 3: exit 0" test $rc -eq 0
check "--time 3: the render loop ended within the budget + 2 s" num "$render_s" '<' 5
check "--time 3: the process ended within budget + set-up + 4 s" \
    num "$wall" '<' "$(awk -v s="$setup_s" 'BEGIN { print s + 7 }')"
check "--time 3: it rendered for most of the budget" num "$render_s" '>' 2
check "--time 3: the EXR records its spp" num "$spp" '>=' 1
check "--time 3: the JSON's spp is the EXR's" test "$(jnum "$T/t.json" .spp)" = "$spp"
check "--time 3: the EXR records the budget" test "$(exr_attr "$T/t.exr" specmip:timeBudgetSeconds)" = 3
check "--time 3: the JSON says the budget ended it" test "$(jq .time_up "$T/t.json")" = true
check "--time 3: says the budget ended it" said "the time budget (3 s) ended the render at $spp samples per pixel"

# 2. With --spp: whichever limit comes first.
"$BIN" render --time 1000 --spp 4 -o "$T/s.exr" 2> "$T/err"
check "--time 1000 --spp 4: exit 0 at 4 spp" test $? -eq 0 -a "$(exr_attr "$T/s.exr" samplesPerPixel)" = 4
check "--time 1000 --spp 4: not ended by the budget" not_grep "time budget" "$T/err"

# 3. Checkpoints every 0.5 s of a long render (256x192: 1 spp a pass), read
#    as they come: each read must decode every pixel of the EXR and the PNG.
R=(render --width 256 --height 192 --seed 5 --quiet)
"$BIN" "${R[@]}" --spp 100000 --checkpoint 0.5 -o "$T/c.exr" -o "$T/c.png" 2> "$T/cerr" &
pid=$!
seen="" bad=0 snap=""
for ((i = 0; i < 200; i++)); do
    sleep 0.2
    kill -0 $pid 2> /dev/null || break
    # the first checkpoint writes the film, the EXR, then the PNG: all there
    [ -e "$T/c.exr.film" ] && [ -e "$T/c.exr" ] && [ -e "$T/c.png" ] || continue
    cp "$T/c.exr" "$T/read.exr" && cp "$T/c.png" "$T/read.png" && cp "$T/c.exr.film" "$T/read.film"
    if ! oiiotool "$T/read.exr" --printstats > /dev/null 2>&1 ||
        ! oiiotool "$T/read.png" --printstats > /dev/null 2>&1; then
        bad=$((bad + 1))
        continue
    fi
    s=$(exr_attr "$T/read.exr" samplesPerPixel)
    case " $seen " in *" $s "*) ;; *) seen="$seen $s" ;; esac
    if [ -z "$snap" ] && [ "$(film_samples "$T/read.film")" = "$s" ]; then # a pair to resume
        snap=$s && mkdir "$T/snap" && cp "$T/read.exr" "$T/snap/c.exr" && cp "$T/read.film" "$T/snap/c.exr.film"
    fi
    [ "$(echo $seen | wc -w)" -ge 4 ] && break
done
kill -INT $pid
wait $pid
rc=$?
echo "  checkpoints read at spp:$seen (unreadable reads: $bad)"
check "checkpoints: interrupted at last (exit 130)" test $rc -eq 130
check "checkpoints: every read decoded" test $bad -eq 0
check "checkpoints: at least 4 seen" test "$(echo $seen | wc -w)" -ge 4
check "checkpoints: said on stderr" grep -q "checkpoint: [0-9]* samples per pixel written" "$T/cerr"
increasing() { echo $seen | tr ' ' '\n' | sort -n -c 2> /dev/null; }
check "checkpoints: spp grows" increasing
check "checkpoints: a film and EXR pair read" test -n "$snap"
# The film read mid-render, resumed 2 spp further: one render to that spp.
n=$((${snap:-0} + 2))
"$BIN" "${R[@]}" --spp $n --resume "$T/snap/c.exr" 2> "$T/err"
check "checkpoint's film: resumed" test $? -eq 0
"$BIN" "${R[@]}" --spp $n -o "$T/one.exr"
check "checkpoint's film: resumed to $n spp, bit for bit one render" same_pixels "$T/one.exr" "$T/snap/c.exr"
finish
