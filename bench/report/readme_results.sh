#!/bin/bash
# Puts the generated docs/RESULTS.md into README.md between the markers
# "<!-- results:begin -->" and "<!-- results:end -->" (headings one level
# down, chart paths under docs/), so README's numbers are never typed by hand.
# usage: bench/report/readme_results.sh [RESULTS.md] [README.md]
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
res=${1:-$root/docs/RESULTS.md}
readme=${2:-$root/README.md}
grep -q '^<!-- results:begin -->$' "$readme" && grep -q '^<!-- results:end -->$' "$readme" ||
    { echo "readme_results.sh: $readme has no results markers" >&2; exit 2; }
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
awk -v res="$res" '
    /^<!-- results:begin -->$/ {
        print
        while ((getline line < res) > 0) {
            if (line ~ /^# /) continue                      # the file title
            if (line ~ /^#/) line = "#" line                # one level down
            if (line ~ /^!\[/) sub(/\]\(/, "](docs/", line) # charts live in docs/
            print line
        }
        skip = 1
        next
    }
    /^<!-- results:end -->$/ { skip = 0 }
    !skip' "$readme" > "$tmp"
cat "$tmp" > "$readme"
