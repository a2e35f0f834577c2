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

# data/records/logger-semicolon.csv: the same kind of passage as a field logger writes it (issue
# #19): a preamble, semicolons and decimal commas, units in brackets ([g], [m/s^2], [mm], [µε]),
# 1651.2 Hz with time stamps rounded to 0.1 ms, 1 s of logging before the train, three NaN
# acceleration samples, an empty strain cell and a 4-sample gap in the time column. Old Guadiana
# under the Talgo at 154.8 km/h, Newmark at the logger's rate, strain at 0.8 m below the neutral
# axis of S1_mid; white noise of 3 % of each channel's RMS (seed 19).
"$V" run scenarios/old-guadiana-talgo.toml --set analysis.dt=0.000605620155038760 --set filter.enabled=false \
  --set 'stations[0].fibre_m=0.8' --quiet --out "$tmp/logger"
/usr/bin/python3 - "$tmp/logger/history.csv" data/records/logger-semicolon.csv <<'PY'
import sys
import numpy as np
src, dst = sys.argv[1:3]
d = np.genfromtxt(src, delimiter=",", names=True)
fs = 1651.2
lead = int(round(1.0 * fs))
cols = [("Acc S1 mid [g]", d["S1_mid_acc_mps2"] / 9.80665, "%.6f"),
        ("Acc S2 mid [m/s^2]", d["S2_mid_acc_mps2"], "%.5f"),
        ("Disp S1 mid [mm]", 1e3 * d["S1_mid_disp_m"], "%.4f"),
        ("Strain S1 mid [µε]", d["S1_mid_strain_ue"], "%.3f")]
rng = np.random.default_rng(19)
data = []
for name, x, fmt in cols:
    x = np.concatenate([np.zeros(lead), x])
    data.append(x + rng.normal(0.0, 0.03 * np.sqrt(np.mean(x[lead:] ** 2)), x.size))
n = data[0].size
t = 125.0 + np.arange(n) / fs
gap = set(range(lead + 1500, lead + 1504))   # the logger's buffer overran: 4 samples never written
nan_acc = {lead + 400, lead + 401, lead + 2600}
blank_strain = {lead + 900}
with open(dst, "w", encoding="utf-8", newline="") as f:
    f.write("DX-100 data logger export\r\nSite;Old Guadiana bridge (synthetic: scripts/generate/make_synthetic_records.sh)\r\n")
    f.write("Start;2026-05-14 10:31:07\r\nSample rate;1651,2 Hz\r\n")
    f.write("Time [s];" + ";".join(c[0] for c in cols) + "\r\n")
    for k in range(n):
        if k in gap:
            continue
        cells = ["%.4f" % (round(t[k] * 1e4) / 1e4)]
        for j, (name, x, fmt) in enumerate(cols):
            if j < 2 and k in nan_acc:
                cells.append("NaN")
            elif j == 3 and k in blank_strain:
                cells.append("")
            else:
                cells.append(fmt % data[j][k])
        f.write(";".join(c.replace(".", ",") for c in cells) + "\r\n")
PY
echo "wrote data/records/logger-semicolon.csv ($(wc -l < data/records/logger-semicolon.csv) lines)"
