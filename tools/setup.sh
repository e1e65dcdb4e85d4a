#!/usr/bin/env bash
# Installs what specmip needs from Debian 12 (as root) and builds it into build/.
# Usage: bash tools/setup.sh [--bench] [extra cmake options]
# --bench also installs Embree 3 (libembree-dev), optional and used only by
# `specmip bench --rays --embree` (bench/scale.sh), and Blender's data
# (blender-data: its CC0 studio-light HDRIs, /usr/share/blender/datafiles/
# studiolights/world/*.exr, for bench/envmap_palette.c): nothing else needs them.
set -euo pipefail
cd "$(dirname "$0")/.."
bench=()
if [ "${1:-}" = --bench ]; then
  bench=(libembree-dev blender-data)
  shift
fi

# The build: compiler, CMake, OpenCL headers and loader, PoCL, OpenImageIO,
# Assimp (mesh files).
# The tests and scripts: oiiotool/idiff (openimageio-tools), python3, jq,
# GNU time (/usr/bin/time), gnuplot (bench charts), clinfo; Mesa's Rusticl
# (mesa-opencl-icd) and Oclgrind, the second and third OpenCL implementations
# the suite checks the kernels on. OpenMPI (libopenmpi-dev, openmpi-bin) for a
# render across processes and machines (mpirun; the build works without it),
# procps (pgrep) for its tests. python3-venv for the test suite's Python
# environment (below).
packages=(build-essential cmake pkg-config ocl-icd-opencl-dev opencl-headers pocl-opencl-icd
          libopenimageio-dev openimageio-tools libassimp-dev libexpat1-dev python3 python3-venv jq time gnuplot-nox
          clinfo mesa-opencl-icd oclgrind libopenmpi-dev openmpi-bin procps "${bench[@]}")
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"$(nproc)"

# The suite's Python environment, beside the build: colour-science and
# OpenImageIO's Python module from PyPI (Debian 12 packages neither
# colour-science nor a numpy it supports), each wheel pinned by its SHA-256
# in tests/python-requirements.txt, in a venv of Debian's Python so that the
# system stays as it is. Where PyPI's certificate cannot be verified (a
# network that re-signs TLS with a CA this system lacks) pip is asked again
# without the certificate check: the pinned hashes still admit only those
# files.
venv=build/pyenv
req=tests/python-requirements.txt
if ! "$venv/bin/python" -c "import colour, OpenImageIO" 2>/dev/null; then
  echo "setup: installing colour-science and OpenImageIO (PyPI) into $venv" >&2
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv"
  pipi=("$venv/bin/pip" install -q --disable-pip-version-check --require-hashes --only-binary=:all: -r "$req")
  if ! PIP_FIND_LINKS= "${pipi[@]}" --retries 1 2>/dev/null; then
    echo "setup: PyPI's certificate not verified here; installing by the pinned SHA-256 alone" >&2
    PIP_FIND_LINKS= "${pipi[@]}" --trusted-host pypi.org --trusted-host files.pythonhosted.org
  fi
fi
