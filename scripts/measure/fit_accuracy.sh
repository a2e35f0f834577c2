#!/usr/bin/env bash
# Measures how well viaduct fit recovers known parameters from synthetic records (a small span at
# three noise levels, 20 realisations each; the Old Guadiana model, 5 realisations) and writes
# docs/fitting-accuracy.md. About 3 minutes.
#   scripts/measure/fit_accuracy.sh [SEEDS]
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/measure/lib.sh
seeds=${1:-20}
release_build
out=docs/fitting-accuracy.md
{
  echo "# Model updating: measured recovery errors"
  echo
  echo "Written by \`scripts/measure/fit_accuracy.sh\` (\`build/release/viaduct_fit_recovery . $seeds\`, source in"
  echo "\`tools/bench/fit_recovery.cpp\`, records made by \`tests/unit/study/fit_synthetic.hpp\`) on"
  echo "$(date -u +%Y-%m-%d), $(nproc) cores, 2 threads per fit. Method: [fitting.md](fitting.md)."
  echo
  echo "The small span: 12 m, EI = 5.5e9 N·m², 10 t/m, modal damping 2.5 %, three 100 kN axles 8 m apart"
  echo "at 30 m/s, deck accelerations at L/2 and L/4 (500 Hz, 0.7 s of logging before the train),"
  echo "filter 1–30 Hz; fitted: EI in [3e9, 8e9] from 5.0e9 and ζ in [0.005, 0.08] from 0.015, objective"
  echo "\`time\`. The Old Guadiana case: the scenario \`old-guadiana-talgo.toml\` (528 DOFs, Newmark 1 ms)"
  echo "made with EI = 7.8e9, pad stiffness 2e8 N/m and ζ₁ = 2.5 %, recorded at mid-span of both spans at"
  echo "1 kHz after 1.5 s of logging; fitted from the scenario's 7.09e9, 1e8, 3.1 %."
  echo "Fit times here are indicative (other work may share the machine); the benchmark is"
  echo "[benchmarks-fitting.md](benchmarks-fitting.md)."
  echo
  build/release/viaduct_fit_recovery . "$seeds"
} > "$out.tmp"
mv "$out.tmp" "$out"
echo "wrote $out"
