#!/usr/bin/env bash
# Every function of the C and OpenCL C sources under the given folders (or
# files), longest first: "LINES FILE:LINE NAME". A function is what the
# project's style writes as one: a declaration starting at column 0, its body
# opening with a '{' alone at column 0 and closing with a '}' alone at column
# 0; its lines counted from the declaration's first to the closing brace.
# Usage: tools/function_lengths.sh [-l LIMIT] PATH...   (-l: only those over LIMIT)
set -euo pipefail
limit=0
if [ "${1:-}" = -l ]; then
  limit=$2
  shift 2
fi
[ $# -gt 0 ] || { echo "usage: $0 [-l LIMIT] PATH..." >&2; exit 2; }
find "$@" -type f \( -name '*.c' -o -name '*.h' -o -name '*.cl' -o -name '*.clh' \) -print0 |
  sort -z | xargs -0 awk -v limit="$limit" '
    FNR == 1 { start = 0; infn = 0 }
    !infn && /^[A-Za-z_]/ && !/;[ \t]*$/ && !start { start = FNR; sig = $0 }
    !infn && /^[A-Za-z_].*;[ \t]*$/ { start = 0 }
    !infn && /^$/ { start = 0 }
    !infn && /^\{[ \t]*$/ && start { infn = 1; next }
    infn && /^\}[ \t]*$/ {
        n = FNR - start + 1
        name = sig; sub(/\(.*/, "", name); sub(/.*[ \t*]/, "", name)
        if (n > limit) printf "%d %s:%d %s\n", n, FILENAME, start, name
        infn = 0; start = 0
    }' | sort -rn
