#!/usr/bin/env bash
# Simulated recorded passages for `viaduct passages` (issue #19 part 5): the 15 m HSLM span of
# scenarios/hslm-simply-supported.toml (strain gauge 0.6 m below the neutral axis) under
# HSLM-A1, HSLM-A7 and the Talgo Altaria, each passage simulated by `viaduct run` (Newmark, 1 ms,
# unfiltered), decimated to 250 Hz with SciPy's zero-phase FIR anti-alias filter, 1 s of quiet
# logging put before the train, and white noise of 5 % of each channel's RMS over the passage
# added (seeded). Channels mid_acc_mps2, mid_disp_m, mid_strain_ue; a table passages.csv
# (file,train,speed_kmh,true_speed_kmh) with speed_kmh empty: `viaduct passages` identifies it.
#
#   scripts/generate/make_passages.sh [VIADUCT] [OUT] [N]
# N = 3 (default) writes the committed sample data/records/passages/; N = 20 the set of the
# README's passage check (speeds scattered over 160-400 km/h, seed 19).
set -euo pipefail
cd "$(dirname "$0")/../.."
V=${1:-build/release/viaduct}
OUT=${2:-data/records/passages}
N=${3:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$OUT"
# The passages: train file (from the repository root) and speed [km/h].
/usr/bin/python3 - "$N" > "$tmp/list" <<'PY'
import sys
import numpy as np
n = int(sys.argv[1])
trains = ["data/trains/hslm/A1.toml", "data/trains/hslm/A7.toml", "data/trains/talgo-altaria.csv"]
if n == 3:
    plan = [(trains[0], 252.0), (trains[2], 183.0), (trains[1], 331.0)]
else:
    rng = np.random.default_rng(19)
    plan = [(trains[k % 3], round(float(rng.uniform(160.0, 400.0)), 1)) for k in range(n)]
for t, v in plan:
    print(t, v)
PY
echo "file,train,speed_kmh,true_speed_kmh" > "$OUT/passages.csv"
k=0
while read -r train v; do
  k=$((k + 1))
  name=$(printf 'passage-%02d.csv' "$k")
  "$V" run scenarios/hslm-simply-supported.toml --set "train.files=[\"$train\"]" --set run.speed_kmh="$v" \
    --set 'stations[0].fibre_m=0.6' --set filter.enabled=false --quiet --out "$tmp/run"
  tname=$(grep -m1 '^name' "$train" 2>/dev/null | sed 's/.*= *"\(.*\)"/\1/' || true)
  [ -n "$tname" ] || tname="$(python3 -c "import os,sys; print(os.path.relpath(sys.argv[1], sys.argv[2]))" "$train" "$OUT")"
  /usr/bin/python3 - "$tmp/run/history.csv" "$OUT/$name" "$k" "$train" "$v" "$("$V" --version | cut -d' ' -f2)" <<'PY'
import sys
import numpy as np
from scipy.signal import decimate
src, dst, seed, train, v, version = sys.argv[1:7]
d = np.genfromtxt(src, delimiter=",", names=True)
chans = ["mid_acc_mps2", "mid_disp_m", "mid_strain_ue"]
q = 4  # 1000 Hz -> 250 Hz
fs = 1000.0 / q
lead = int(fs)  # 1 s before the train
rng = np.random.default_rng(100 + int(seed))
cols = []
for c in chans:
    x = decimate(d[c], q, ftype="fir", zero_phase=True)
    x = x + rng.normal(0.0, 0.05 * np.sqrt(np.mean(x ** 2)), x.size)
    cols.append(np.concatenate([rng.normal(0.0, 0.05 * np.sqrt(np.mean(x ** 2)), lead), x]))
with open(dst, "w") as f:
    f.write("# Simulated passage made by viaduct %s (scripts/generate/make_passages.sh): the 15 m HSLM span\n" % version)
    f.write("# of scenarios/hslm-simply-supported.toml, %s at %s km/h, 1 s of logging before the train,\n" % (train, v))
    f.write("# decimated to 250 Hz, white noise of 5 %% of each channel's RMS (seed %d).\n" % (100 + int(seed)))
    f.write("# sampling_rate_hz = 250\n")
    f.write("t_s," + ",".join(chans) + "\n")
    for k in range(cols[0].size):
        f.write("%.3f,%s\n" % (k / fs, ",".join("%.4e" % x[k] for x in cols)))
PY
  echo "$name,$tname,,$v" >> "$OUT/passages.csv"
done < "$tmp/list"
echo "wrote $k passages and $OUT/passages.csv"
