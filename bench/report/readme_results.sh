#!/bin/bash
# Puts README's headline table, generated from docs/RESULTS.md, between the
# markers "<!-- results:begin -->" and "<!-- results:end -->": per scene, each
# mode's mean error at equal time (the 1x budget) and the scene's floor. The
# rest of the results stays in docs/RESULTS.md only, so no number is typed by
# hand and none is kept twice.
# usage: bench/report/readme_results.sh [RESULTS.md] [README.md]
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
res=${1:-$root/docs/RESULTS.md}
readme=${2:-$root/README.md}
grep -q '^<!-- results:begin -->$' "$readme" && grep -q '^<!-- results:end -->$' "$readme" ||
    { echo "readme_results.sh: $readme has no results markers" >&2; exit 2; }
tmp=$(mktemp)
table=$(mktemp)
trap 'rm -f "$tmp" "$table"' EXIT
awk -F'|' '
    function trim(s) { gsub(/^[ \t]+|[ \t]+$/, "", s); return s }
    /^## / { scene = substr($0, 4); col = 0; next }
    /^Measured / && !when { when = $0; sub(/^Measured /, "", when); sub(/ on .*/, "", when) }
    /error floor/ { f = $0; sub(/.*mean /, "", f); sub(/,.*/, "", f); floor[scene] = f }
    /^\| mode \|/ {
        col = 0
        for (i = 2; i < NF; i++) if (trim($i) == "mean 1×") col = i
        next
    }
    col && /^\|---/ { next }
    col && /^\|/ {
        m = trim($2)
        if (!(m in seen)) { seen[m] = 1; modes[++nm] = m }
        if (!(scene in sseen)) { sseen[scene] = 1; scenes[++ns] = scene }
        err[scene, m] = trim($col)
        next
    }
    col && !/^\|/ { col = 0 }
    END {
        if (ns == 0) { print "readme_results.sh: no equal-time tables in the results" > "/dev/stderr"; exit 2 }
        printf "| scene | floor"; for (j = 1; j <= nm; j++) printf " | %s", modes[j]; print " |"
        printf "|---|---:"; for (j = 1; j <= nm; j++) printf "|---:"; print "|"
        for (i = 1; i <= ns; i++) {
            s = scenes[i]; printf "| %s | %s", s, floor[s]
            for (j = 1; j <= nm; j++) printf " | %s", err[s, modes[j]]
            print " |"
        }
        print ""
        print "Mean ΔE00 against a converged truth after a 5×5 blur, each mode at the spp that takes ref’s"
        print "time at 64 spp (96×96; measured " when "); the floor is two converged truths apart, lower is"
        print "better. Generated from [docs/RESULTS.md](docs/RESULTS.md) by `bench/report/readme_results.sh`."
    }' "$res" > "$table"
awk -v table="$table" '
    /^<!-- results:begin -->$/ {
        print
        while ((getline line < table) > 0) print line
        skip = 1
        next
    }
    /^<!-- results:end -->$/ { skip = 0 }
    !skip' "$readme" > "$tmp"
cat "$tmp" > "$readme"
