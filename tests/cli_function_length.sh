#!/bin/bash
# No function over 120 lines in host/, kernels/ or include/ (the project's
# style: a function longer than a screen is split where its steps are), as
# tools/function_lengths.sh counts them. Needs no device.
source "$(dirname "$0")/lib_cli.sh"

LIMIT=120
long=$("$ROOT/tools/function_lengths.sh" -l $LIMIT "$ROOT/host" "$ROOT/kernels" "$ROOT/include")
[ -z "$long" ] || printf '  over %d lines: %s\n' $LIMIT "$long" >&2
check "no function over $LIMIT lines in host/, kernels/, include/" test -z "$long"
check "the count sees the trace loop" \
    grep -q " spm_trace$" <("$ROOT/tools/function_lengths.sh" "$ROOT/kernels/trace.cl")

# the count itself can fail: a function of LIMIT + 1 lines is reported, one
# of LIMIT lines is not (a C declaration line, the braces, the body)
fn() { # fn NAME LINES: a function of LINES lines in the project's style
    printf 'static int %s(int a)\n{\n' "$1"
    for ((i = 0; i < $2 - 4; i++)); do printf '    a += %d;\n' $i; done
    printf '    return a;\n}\n\n'
}
{ fn fits $LIMIT; fn too_long $((LIMIT + 1)); } > "$T/long.c"
"$ROOT/tools/function_lengths.sh" -l $LIMIT "$T/long.c" > "$T/found"
check "a function of $((LIMIT + 1)) lines is reported" grep -q "^$((LIMIT + 1)) .* too_long$" "$T/found"
check "one of $LIMIT lines is not" test "$(wc -l < "$T/found")" -eq 1
finish
