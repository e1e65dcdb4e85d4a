#!/bin/bash
# 'background sky' refuses what it cannot render: a missing elevation, a
# turbidity outside the model's fit, an option given twice, a sky beside
# another background -- exit 2, the message naming file, line and problem,
# no image written.
source "$(dirname "$0")/lib_cli.sh"

head='image 8 8
camera position 0 1 0 direction 0 0 1 fov 40
spectrum g equal
material m reflect g
quad m -1 0 -1  -1 0 1  1 0 1  1 0 -1'
n=0
refuse() { # refuse LINE MESSAGE [LINENO, default 6]
    n=$((n + 1))
    printf '%s\n%s\n' "$head" "$1" > "$T/s$n.scene"
    "$BIN" render "$T/s$n.scene" --spp 1 --quiet -o "$T/s$n.png" 2> "$T/err"
    local rc=$?
    [ $rc -eq 2 ] && ok || bad "'$1': exit $rc, not 2"
    grep -qF "s$n.scene:${3:-6}:" "$T/err" && grep -qF "$2" "$T/err" && ok ||
        bad "'$1': the message does not name the line and '$2': $(cat "$T/err")"
    [ ! -e "$T/s$n.png" ] && ok || bad "'$1': an image was written"
}
refuse 'background sky turbidity 3' "a sky needs 'elevation DEG' and 'turbidity T'"
refuse 'background sky elevation 30 turbidity 12' 'expected a turbidity (1.7 to 10)'
refuse 'background sky elevation 95 turbidity 3' "expected the sun's elevation in degrees (0 to 90)"
refuse 'background sky elevation 30 turbidity 3 elevation 20' "(each once)"
refuse 'background up g
background sky elevation 30 turbidity 3' 'background up given twice' 7
finish
