#!/usr/bin/env bash
# Regenerates data/records/synthetic-deck.csv: a record made by viaduct with known content
# (the Old Guadiana model under the Talgo Altaria at 154.8 km/h, Newmark dt = 2 ms, deck
# mid-span of span 1, unfiltered deflection and acceleration). Run after building the release
# preset: scripts/generate/make_synthetic_records.sh [path/to/viaduct]
set -euo pipefail
cd "$(dirname "$0")/../.."
V=${1:-build/release/viaduct}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$V" run scenarios/old-guadiana-talgo.toml --set analysis.dt=0.002 --set filter.enabled=false --quiet --out "$tmp"
{
  echo "# Synthetic record made by viaduct $("$V" --version | cut -d' ' -f2) (scripts/generate/make_synthetic_records.sh):"
  echo "# Old Guadiana model, Talgo Altaria at 154.8 km/h, dt = 2 ms, deck at mid-span 1, unfiltered."
  echo "# Known content: first bending mode 10.01 Hz; axle passages of the Talgo rake every 13.14 m (0.306 s, 3.27 Hz)."
  echo "# sampling_rate_hz = 500"
  echo "t_s,deck_disp_m,deck_acc_mps2"
  awk -F, 'NR > 1 { printf "%s,%s,%s\n", $1, $2, $3 }' "$tmp/history.csv"
} > data/records/synthetic-deck.csv
echo "wrote data/records/synthetic-deck.csv ($(wc -l < data/records/synthetic-deck.csv) lines)"

# data/records/og-calibration.csv: a "measured" passage for the model-updating walk-through
# (README, docs/fitting.md), made with parameters the scenario does not have: EI = 7.8e9 N·m²
# (scenario 7.09e9), pad stiffness 2e8 N/m (1e8), damping 2.5 % at 10.065 Hz (3.1 %). Newmark
# 1 ms, 3 s of free vibration; decimated to 500 Hz with SciPy's zero-phase FIR anti-alias
# filter; 1.5 s of quiet logging before the train; white noise of 5 % of the span-1 RMS
# (seed 6). Deck mid-span of both spans, unfiltered.
"$V" run scenarios/old-guadiana-talgo.toml --set bridge.EI=7.8e9 --set track.pad.k=2e8 \
  --set bridge.damping.ratio1=0.025 --set filter.enabled=false --set analysis.free_vibration_s=3 \
  --quiet --out "$tmp/cal"
/usr/bin/python3 - "$tmp/cal/history.csv" data/records/og-calibration.csv "$("$V" --version | cut -d' ' -f2)" <<'PY'
import sys
import numpy as np
from scipy.signal import decimate
src, dst, version = sys.argv[1:4]
d = np.genfromtxt(src, delimiter=",", names=True)
fs = 1.0 / (d["t_s"][1] - d["t_s"][0])
chans = ["S1_mid_acc_mps2", "S2_mid_acc_mps2"]
lead = int(1.5 * fs / 2)
out = [np.concatenate([np.zeros(lead), decimate(d[c], 2, ftype="fir", zero_phase=True)]) for c in chans]
rng = np.random.default_rng(6)
sigma = 0.05 * np.sqrt(np.mean(out[0][lead:] ** 2))
out = [x + rng.normal(0.0, sigma, x.size) for x in out]
with open(dst, "w") as f:
    f.write("# Synthetic record made by viaduct %s (scripts/generate/make_synthetic_records.sh): the Old Guadiana\n" % version)
    f.write("# model under the Talgo Altaria at 154.8 km/h with EI = 7.8e9 N m2, track.pad.k = 2e8 N/m and\n")
    f.write("# damping 2.5 % at 10.065 Hz (the scenario has 7.09e9, 1e8, 3.1 %); 1.5 s of logging before the\n")
    f.write("# train; deck mid-span of spans 1 and 2, unfiltered, white noise of %.3g m/s2 (5 %% of the RMS).\n" % sigma)
    f.write("# sampling_rate_hz = %g\n" % (fs / 2))
    f.write("t_s," + ",".join(chans) + "\n")
    for k in range(out[0].size):
        f.write("%.3f,%s\n" % (k / (fs / 2), ",".join("%.5e" % x[k] for x in out)))
PY
echo "wrote data/records/og-calibration.csv ($(wc -l < data/records/og-calibration.csv) lines)"
