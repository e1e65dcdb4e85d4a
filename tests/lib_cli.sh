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
finish() {
    echo "$pass passed, $fail failed"
    [ "$fail" -eq 0 ]
}
