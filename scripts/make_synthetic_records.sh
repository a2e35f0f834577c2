#!/usr/bin/env bash
# Regenerates data/records/synthetic-deck.csv: a record made by viaduct with known content
# (the Old Guadiana model under the Talgo Altaria at 154.8 km/h, Newmark dt = 2 ms, deck
# mid-span of span 1, unfiltered deflection and acceleration). Run after building the release
# preset: scripts/make_synthetic_records.sh [path/to/viaduct]
set -euo pipefail
cd "$(dirname "$0")/.."
V=${1:-build/release/viaduct}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$V" run scenarios/old-guadiana-talgo.toml --set analysis.dt=0.002 --set filter.enabled=false --quiet --out "$tmp"
{
  echo "# Synthetic record made by viaduct $("$V" --version | cut -d' ' -f2) (scripts/make_synthetic_records.sh):"
  echo "# Old Guadiana model, Talgo Altaria at 154.8 km/h, dt = 2 ms, deck at mid-span 1, unfiltered."
  echo "# Known content: first bending mode 10.01 Hz; axle passages of the Talgo rake every 13.14 m (0.306 s, 3.27 Hz)."
  echo "# sampling_rate_hz = 500"
  echo "t_s,deck_disp_m,deck_acc_mps2"
  awk -F, 'NR > 1 { printf "%s,%s,%s\n", $1, $2, $3 }' "$tmp/history.csv"
} > data/records/synthetic-deck.csv
echo "wrote data/records/synthetic-deck.csv ($(wc -l < data/records/synthetic-deck.csv) lines)"
