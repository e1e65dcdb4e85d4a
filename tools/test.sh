#!/usr/bin/env bash
# Installs, builds and runs every test: the normal build (PoCL, and the kernels
# on Mesa's Rusticl and under Oclgrind: ctest labels rusticl, oclgrind), then the
# host code and the CPU reference again under AddressSanitizer +
# UndefinedBehaviorSanitizer. Sets up with --bench, so the Embree comparison
# builds and runs too and nothing should skip; ends with the tests that were
# skipped (exit 77), if any.
# Usage (as root on Debian 12): bash tools/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh --bench
# compiled kernels: PoCL's and Rusticl's caches beside the build
export POCL_CACHE_DIR="${POCL_CACHE_DIR:-$PWD/build/pocl-cache}"
export MESA_SHADER_CACHE_DIR="${MESA_SHADER_CACHE_DIR:-$PWD/build/mesa-cache}"
# the RGB-to-spectrum table (host/scene/rgb2spec_table.c), fitted once for the suite, not in $HOME
export SPECMIP_CACHE_DIR="${SPECMIP_CACHE_DIR:-$PWD/build/specmip-cache}"
# fitted here, before ctest -j2 starts: two processes that both find no table
# both fit it (on both cores, well over a minute of CPU each)
build/specmip render scenes/envmap.scene --backend cpu --spp 1 --width 4 --height 4 --quiet \
  -o build/rgb2spec-fit.png || echo "test.sh: the RGB-to-spectrum table was not fitted ahead" >&2
ctest --test-dir build --output-on-failure -j2 | tee build/ctest.log

# Sanitizer build: the OpenCL tests are left out (PoCL's LLVM and the ICD
# loader are not instrumented and report their own leaks).
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPECMIP_SANITIZE=ON >/dev/null
cmake --build build-asan -j"$(nproc)"
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j2 -LE opencl | tee build-asan/ctest.log

# ctest lists a skipped test as "NN - NAME (Skipped)" among those that did not run
skipped=$(sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (Skipped)$/\1/p' build/ctest.log build-asan/ctest.log)
if [ -n "$skipped" ]; then
  echo "test.sh: skipped (exit 77):"
  sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (Skipped)$/  build:      \1/p' build/ctest.log
  sed -n 's/^[[:space:]]*[0-9]* - \(.*\) (Skipped)$/  build-asan: \1/p' build-asan/ctest.log
else
  echo "test.sh: no test skipped"
fi
