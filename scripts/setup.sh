#!/usr/bin/env bash
# Installs the Debian packages viaduct needs, only those that are missing.
# Needs root (or sudo) when something is missing; does nothing otherwise.
#   --tests: also what only the tests need (scripts/test.sh passes it): Chromium and pdftotext,
#            which render assess's report.html and read its report.pdf (tests/cli/report_html.sh).
#            viaduct assess prints report.pdf with Chromium when it is there. And ccache, through
#            which the ci and sanitize presets compile (CI builds a fresh clone each time).
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev          # linear algebra (dense and sparse)
  libfftw3-dev           # FFT (signal module)
  libsundials-dev        # IDA (solve module)
  libsuitesparse-dev     # KLU: sparse direct solver inside IDA's Newton iterations
  libspectra-dev         # partial sparse eigenproblems (modal bases of large models)
  libceres-dev           # bounded nonlinear least squares (viaduct fit, model updating)
  libboost-program-options-dev  # the CLI
  catch2                 # tests (v2)
  libtoml11-dev          # scenario files
  libmatio-dev           # MATLAB .mat records (v4, v5, v7.3)
  libopenmpi-dev openmpi-bin  # mpirun -n N viaduct sweep: sampled studies over MPI ranks (issue #16)
  python3 python3-numpy python3-matplotlib  # plot scripts
  python3-scipy          # regenerating the committed filter reference vectors only
  python3-dev python3-pybind11  # the Python package (issue #17: python/, docs/python.md)
  python3-pytest python3-pandas  # its tests (tables as DataFrames when pandas is there)
)
if [ "${1:-}" = "--tests" ]; then
  packages+=(chromium poppler-utils)  # report.html rendered headless, report.pdf's text (tests only)
  packages+=(ccache)  # compiler cache: a fresh clone reuses the objects of earlier builds (CMakeLists.txt, VIADUCT_CCACHE)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "viaduct setup: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "viaduct setup: need root to install: ${missing[*]}" >&2
    exit 1
  fi
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
