#!/usr/bin/env bash
# Installs the Debian packages viaduct needs, only those that are missing.
# Needs root (or sudo) when something is missing; does nothing otherwise.
#   (none):  what building everything needs: the command, the Python package, MPI runs, the plots.
#   --demo:  only what scripts/demo.sh builds and runs (the command and its plot): without
#            SUNDIALS (demo.sh then builds without the IDA method), OpenMPI, pybind11, pytest,
#            pandas and SciPy (CMake takes them when present). libsundials-dev alone depends on
#            mpi-default-dev, petsc-dev, libhypre-dev and gfortran: on a fresh bookworm with g++ and
#            cmake, 168 packages (114 MB) instead of 300 (217 MB); docs/benchmarks.md.
#   --tests: everything, and what only the tests need (scripts/test.sh passes it): Chromium and
#            pdftotext, which render assess's report.html and read its report.pdf
#            (tests/cli/report_html.sh); viaduct assess prints report.pdf with Chromium when it is
#            there. And ccache, through which the ci and sanitize presets compile (CI builds a
#            fresh clone each time).
set -euo pipefail

case "${1:-}" in
  "" | --demo | --tests) ;;
  *) echo "viaduct setup: unknown option '$1' (--demo, --tests, or none)" >&2; exit 2 ;;
esac

packages=(
  g++ cmake ninja-build pkg-config
  libeigen3-dev          # linear algebra (dense and sparse)
  libfftw3-dev           # FFT (signal module)
  libspectra-dev         # partial sparse eigenproblems (modal bases of large models)
  libceres-dev           # bounded nonlinear least squares (viaduct fit, model updating)
  libboost-program-options-dev  # the CLI
  catch2                 # tests (v2)
  libtoml11-dev          # scenario files
  libmatio-dev           # MATLAB .mat records (v4, v5, v7.3)
  python3 python3-numpy python3-matplotlib  # plot scripts
)
if [ "${1:-}" != "--demo" ]; then
  packages+=(libsundials-dev)     # IDA (solve module; CMake VIADUCT_IDA, which the tests need)
  packages+=(libsuitesparse-dev)  # KLU: sparse direct solver inside IDA's Newton iterations
  packages+=(libopenmpi-dev openmpi-bin)  # mpirun -n N viaduct sweep: sampled studies over MPI ranks (issue #16)
  packages+=(python3-scipy)  # regenerating the committed filter reference vectors only
  packages+=(python3-dev python3-pybind11)  # the Python package (issue #17: python/, docs/python.md)
  packages+=(python3-pytest python3-pandas)  # its tests (tables as DataFrames when pandas is there)
fi
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
