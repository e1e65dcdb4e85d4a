#!/bin/bash
# specmip modes: the list scripts read (plain and JSON) names exactly the modes
# that render --mode takes and that its error message offers; each renders.
source "$(dirname "$0")/lib_cli.sh"

"$BIN" modes > "$T/modes.tsv"
check "modes: exit 0" test $? -eq 0
"$BIN" modes --json > "$T/modes.json"
check "modes --json: exit 0" test $? -eq 0
names=$(cut -f1 "$T/modes.tsv" | tr '\n' ' ')
check "modes: some modes" test -n "$names"
check "modes: three tab-separated fields a line" \
    test "$(awk -F'\t' 'NF != 3 || ($2 != "levelled" && $2 != "single")' "$T/modes.tsv" | wc -l)" = 0
check "modes --json: the same names in the same order" \
    test "$(jq -r '.[].name' "$T/modes.json" | tr '\n' ' ')" = "$names"
check "modes --json: the same levelled modes" \
    test "$(jq -r '.[] | select(.levelled) | .name' "$T/modes.json" | tr '\n' ' ')" = \
         "$(awk -F'\t' '$2 == "levelled" { printf "%s ", $1 }' "$T/modes.tsv")"
check "modes --json: help lines" test "$(jq -r '.[].help' "$T/modes.json" | tr '\n' '|')" = \
    "$(cut -f3 "$T/modes.tsv" | tr '\n' '|')"

"$BIN" render --mode no-such-mode --backend cpu -o "$T/x.exr" 2> "$T/err.txt"
check "unknown mode: exit 2" test $? -eq 2
offered=$(sed -n "s/.*unknown mode 'no-such-mode' (\(.*\))$/\1/p" "$T/err.txt" | tr -d ',')
check "unknown mode: the error offers the listed modes" test "$offered " = "$names"
check "render --help lists every mode" \
    test "$("$BIN" render --help | awk -v n="$names" 'BEGIN { split(n, m, " "); for (i in m) want[m[i]] = 1 }
        $1 in want { got[$1] = 1 } END { for (k in want) if (!(k in got)) print k }')" = ""

for m in $names; do
    "$BIN" render --mode "$m" --backend cpu --width 4 --height 3 --spp 1 --quiet -o "$T/$m.exr" \
        > /dev/null 2> "$T/$m.err"
    check "$m renders" test $? -eq 0 -a -s "$T/$m.exr"
done

"$BIN" modes --bogus 2> "$T/bogus.txt"
check "modes --bogus: exit 2" test $? -eq 2
check "modes --bogus: names the option" grep -q "unknown option '--bogus'" "$T/bogus.txt"
finish
