#!/bin/bash
# 'background map FILE': the bundled map is what tools/gen_envmap.py writes;
# scenes/envmap.scene renders in every mode on both backends, lit (the map
# is its only light); bad input is a clear error naming the file, line and
# problem, exit 2, no image written.
# usage: bash tests/cli_envmap.sh /path/to/specmip
source "$(dirname "$0")/lib_cli.sh"

python3 "$ROOT/tools/gen_envmap.py" "$T/sunsky.hdr" &&
  cmp -s "$T/sunsky.hdr" "$ROOT/scenes/sunsky.hdr" && ok ||
  bad "scenes/sunsky.hdr is not what tools/gen_envmap.py writes (regenerate it)"

for backend in opencl cpu; do
  for mode in $("$BIN" modes | cut -f1); do
    out=$T/env-$mode-$backend.exr
    "$BIN" render "$ROOT/scenes/envmap.scene" --mode "$mode" --backend "$backend" \
      --width 24 --height 16 --spp 4 --quiet -o "$out" 2>"$T/err" ||
      { bad "$mode $backend: $(cat "$T/err")"; continue; }
    avg=$(oiiotool "$out" --printstats 2>/dev/null |
          awk -F: '/Stats Avg/ { split($2, v, " "); print v[2]; exit }')
    num "$avg" '>' 0.05 && ok || bad "$mode $backend: the map lights nothing (mean G $avg)"
  done
done

# bad input: exit 2, the statement's place and the problem, no image
body='image 8 8
camera position 0 1 -3 direction 0 0 1 fov 40
spectrum e equal
material m reflect e 0.5
quad m -1 0 -1  -1 0 1  1 0 1  1 0 -1'
refuse() {  # refuse WHAT LINE MESSAGE-PATTERN: the scene with LINE appended
  printf '%s\n%s\n' "$body" "$2" > "$T/bad.scene"
  rm -f "$T/bad.png"
  "$BIN" render "$T/bad.scene" --quiet -o "$T/bad.png" 2>"$T/err"
  rc=$?
  [ $rc -eq 2 ] && grep -qE "bad.scene:6:[0-9]+: .*$3" "$T/err" && [ ! -e "$T/bad.png" ] && ok ||
    bad "$1: exit $rc, $(cat "$T/err")"
}
printf 'not an image\n' > "$T/text.hdr"
cp "$ROOT/scenes/sunsky.hdr" "$T/sunsky.hdr"
refuse "a missing map" "background map nowhere.hdr" "environment map .*nowhere.hdr.* not found"
refuse "not an image" "background map text.hdr" "environment map .*text.hdr.* cannot be read"
refuse "a map outside the scene's folder" "background map /etc/hostname" "hostname"
refuse "an unknown option" "background map sunsky.hdr bright 2" "expected 'scale' or 'rotate'"
refuse "a negative scale" "background map sunsky.hdr scale -1" "scale"
printf '%s\nbackground up e 1\n' "$body" > "$T/twice.scene"
echo "background map sunsky.hdr" >> "$T/twice.scene"
"$BIN" render "$T/twice.scene" --quiet -o "$T/twice.png" 2>"$T/err"
[ $? -eq 2 ] && grep -q "twice.scene:7:.*given twice" "$T/err" && ok ||
  bad "a map after 'background up': $(cat "$T/err")"
finish
