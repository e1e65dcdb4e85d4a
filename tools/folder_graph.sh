#!/bin/bash
# The host folders' link-level dependencies, from the object files' symbols
# (includes would hide them: every host folder is on the include path).
#   tools/folder_graph.sh [OBJDIR]          "from to" per edge: a folder's object
#                                            uses a symbol another folder defines
#   tools/folder_graph.sh --loops [OBJDIR]  the folder pairs that reach each other
#   tools/folder_graph.sh --files FOLDER [--loops] [OBJDIR]
#                                            the same between the files of one
#                                            host folder (a file: its object)
# OBJDIR is spm_core's object directory (default build/CMakeFiles/spm_core.dir);
# an object whose source is gone (a stale one) is left out.
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
loops=0 files=
if [ "${1:-}" = --files ]; then files=$2; shift 2; fi
if [ "${1:-}" = --loops ]; then loops=1; shift; fi
dir=${1:-$src/build/CMakeFiles/spm_core.dir}
objs=$(ls "$dir"/host/${files:-*}/*.o 2>/dev/null) || { echo "folder_graph: no objects in $dir/host/${files}" >&2; exit 2; }
edges=$(for o in $objs; do
    f=$(basename "$(dirname "$o")")
    [ -e "$src/host/$f/$(basename "$o" .o)" ] || continue
    [ -z "$files" ] || f=$(basename "$o" .o)
    nm -g --defined-only "$o" | awk -v f="$f" 'NF == 3 { print "D", $3, f }'
    nm -u "$o" | awk -v f="$f" '{ print "U", $NF, f }'
done | awk '$1 == "D" { def[$2] = $3; next } { use[$2 " " $3] = 1 }
            END { for (k in use) { split(k, a, " "); if (a[1] in def && def[a[1]] != a[2]) print a[2], def[a[1]] } }' |
    sort -u)
if [ $loops = 0 ]; then
    printf '%s\n' "$edges" | sed '/^$/d'
    exit 0
fi
# reachability by closure; a pair is a loop when each reaches the other
printf '%s\n' "$edges" | awk 'NF == 2 { r[$1, $2] = 1; n[$1]; n[$2] }
    END { for (k in n) for (i in n) if (r[i, k]) for (j in n) if (r[k, j]) r[i, j] = 1
          for (i in n) for (j in n) if (i < j && r[i, j] && r[j, i]) print i, j }' | sort
