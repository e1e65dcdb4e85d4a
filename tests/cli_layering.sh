#!/bin/bash
# The layering, enforced: the host folders' dependencies, derived from the
# object files' symbols (tools/folder_graph.sh; includes would hide them),
# are each allowed by docs/ARCHITECTURE.md's "depends on" column (or what
# those folders may use in turn: layers reach only downward), every folder is
# in that table, and no two folders reach each other. Needs no device.
source "$(dirname "$0")/lib_cli.sh"

command -v nm > /dev/null || skip "no nm"
OBJ=$(dirname "$BIN")/CMakeFiles/spm_core.dir
[ -d "$OBJ/host" ] || skip "no object directory beside the binary ($OBJ)"
DOC=$ROOT/docs/ARCHITECTURE.md

# allowed: "from to" for every folder to every folder its documented ones
# reach (the closure of the table's last column; "everything": every folder).
awk -F'|' '$2 ~ /^ *`host\/[a-z]+\/` *$/ {
        f = $2; gsub(/[ `]|host\/|\//, "", f); n[f]; deps[f] = $(NF - 1) }
    END {
        for (f in deps) {
            if (deps[f] ~ /everything/) { for (g in n) if (g != f) r[f, g] = 1; continue }
            k = split(deps[f], d, ",")
            for (i = 1; i <= k; i++) { g = d[i]; gsub(/[ `]/, "", g); if (g in n) r[f, g] = 1 }
        }
        for (k in n) for (i in n) if (r[i, k]) for (j in n) if (r[k, j]) r[i, j] = 1
        for (i in n) for (j in n) if (r[i, j]) print i, j
        for (i in n) print i > "/dev/stderr"
    }' "$DOC" 2> "$T/documented" | sort > "$T/allowed"
# not_allowed EDGES: the edges of the file EDGES that the table does not allow
not_allowed() { sort "$1" | comm -23 - "$T/allowed"; }

"$ROOT/tools/folder_graph.sh" "$OBJ" > "$T/edges"
check "folder_graph: exit 0" test $? -eq 0
check "the graph has edges (objects read)" test "$(wc -l < "$T/edges")" -gt 10
check "ARCHITECTURE.md documents folders" test "$(wc -l < "$T/documented")" -gt 10
for d in "$ROOT"/host/*/; do
    f=$(basename "$d")
    check "host/$f/ is in ARCHITECTURE.md's table" grep -qx "$f" "$T/documented"
done
bad_edges=$(not_allowed "$T/edges")
[ -z "$bad_edges" ] || printf '  not allowed by ARCHITECTURE.md: %s\n' $(echo "$bad_edges" | tr ' ' '>') >&2
check "every folder edge is allowed" test -z "$bad_edges"
loops=$("$ROOT/tools/folder_graph.sh" --loops "$OBJ")
[ -z "$loops" ] || echo "  folders that reach each other:" $(echo "$loops" | sed "s/ /<->/") >&2
check "no folder loops" test -z "$loops"
# within host/scene/ too: the loader calls the parsers, they and the mesh
# statements call the builder, and nothing calls back (a file loop)
scene_loops=$("$ROOT/tools/folder_graph.sh" --files scene --loops "$OBJ")
[ -z "$scene_loops" ] || echo "  host/scene files that reach each other:" $(echo "$scene_loops" | sed "s/ /<->/") >&2
check "no file loops in host/scene/" test -z "$scene_loops"
check "host/scene/ file graph read (the parser calls the builder)" \
    grep -qx "scene_parse.c scene_build.c" <("$ROOT/tools/folder_graph.sh" --files scene "$OBJ")
# the check itself can fail: an upward edge is refused, a documented one not
printf 'util run\n' > "$T/upward"
check "an upward edge (util -> run) is refused" test "$(not_allowed "$T/upward")" = "util run"
printf 'run util\n' > "$T/downward"
check "a downward edge (run -> util) is allowed" test -z "$(not_allowed "$T/downward")"
finish
