# Shared prelude of the shell tests (sourced, not run): the binary from $1,
# the data root, a scratch directory removed on exit, and pass/fail counting
# that ends with the "N passed, N failed" line ctest's log shows.
set -u
BIN=${1:?usage: bash tests/cli_NAME.sh /path/to/specmip}
HERE=$(cd "$(dirname "${BASH_SOURCE[1]}")" && pwd)
ROOT=$(dirname "$HERE")
export SPECMIP_DATA=${SPECMIP_DATA:-$ROOT}
DATA=$SPECMIP_DATA
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
check() {  # check WHAT COMMAND...: counts COMMAND's success
    local what=$1; shift
    if "$@"; then ok; else bad "$what"; fi
}
# rendering PID ERR: true once the render PID has finished a pass (its
# --progress line in ERR), false if it ends first or 60 s go by.
rendering() {
    local i
    for i in $(seq 600); do
        grep -q "pass [1-9][0-9]*/" "$2" 2>/dev/null && return 0
        kill -0 "$1" 2>/dev/null || return 1
        sleep 0.1
    done
    return 1
}
finish() {
    echo "$pass passed, $fail failed"
    [ "$fail" -eq 0 ]
}
