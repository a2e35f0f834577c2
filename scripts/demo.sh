#!/usr/bin/env bash
# The headline study: the Old Guadiana bridge's deck-acceleration envelopes under the paper's
# artificial train for 60 speeds and the Kp/Cp/Kb/Cb track variants (REFERENCE.md §1).
# Installs what is missing, builds (release), runs the sweep on all cores, writes
# out/old-guadiana-sensitivity/{envelope.csv,failures.csv,manifest.toml,envelope.png}.
# Options are passed to `viaduct sweep` (e.g. --set sweep.n_speeds=20 for a quicker look).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --demo  # only what the command and its plot need (scripts/setup.sh alone: everything)
# Without SUNDIALS (setup.sh --demo leaves libsundials-dev out: a third of a fresh machine's first
# five minutes, #37) the command is built without the IDA method, which it then refuses with the
# way to add it; with libsundials-dev installed (scripts/setup.sh), with it.
ida=ON
if ! dpkg-query -W -f='${Status}' libsundials-dev 2>/dev/null | grep -q "install ok installed"; then
  ida=OFF
  echo "demo: building viaduct without the IDA method (libsundials-dev is not installed: scripts/setup.sh adds it)" >&2
fi
cmake --preset release -G Ninja -DVIADUCT_IDA=$ida >/dev/null
# Only what the demo runs: the command (the tests, benchmarks and Python package are
# scripts/test.sh's and `cmake --build --preset release`'s).
cmake --build --preset release -j "$(nproc 2>/dev/null || echo 2)" --target viaduct
# `viaduct` on the PATH for the README's walk-throughs (as root: /usr/local/bin/viaduct).
if [ -w "$(cmake -L -N build/release 2>/dev/null | sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p')/bin" ]; then
  cmake --install build/release --component cli >/dev/null
else
  echo "demo: not installing viaduct (no write access to the install prefix): use build/release/viaduct" >&2
fi
out=out/old-guadiana-sensitivity
build/release/viaduct modes scenarios/old-guadiana-sensitivity.toml --n-modes 10 --out "$out"
build/release/viaduct sweep scenarios/old-guadiana-sensitivity.toml --threads 0 --out "$out" "$@"
/usr/bin/python3 scripts/plot/plot_envelope.py "$out"
echo "results: $out/envelope.csv, plot: $out/envelope.png"
