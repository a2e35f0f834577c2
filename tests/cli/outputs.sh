#!/usr/bin/env bash
# Outputs: history.csv, modes.csv, envelope.csv (tidy columns), manifest.toml; threads agree.
. "$(dirname "$0")/lib.sh"
HS=$SRC/scenarios/hslm-simply-supported.toml
SET=(--set "train.files=[\"$SRC/data/trains/hslm/A1.toml\", \"$SRC/data/trains/hslm/A9.toml\"]" --set sweep.speed_step_kmh=70)
expect 0 "wrote" -- "$VIADUCT" run "$HS" --out "$WORK/run"
expect 0 "t_s,mid_disp_m,mid_acc_mps2,mid_acc_filt_mps2" -- head -1 "$WORK/run/history.csv"
expect 0 "command = \"run\"" -- cat "$WORK/run/manifest.toml"
expect 0 "\"bridge.EI\" = 7694000000.0" -- cat "$WORK/run/manifest.toml"
expect 0 "5.0000" -- "$VIADUCT" modes "$HS" --out "$WORK/modes"
expect 0 "mode,frequency_hz,mid_deck" -- head -1 "$WORK/modes/modes.csv"
expect 0 "10 cases" -- "$VIADUCT" sweep "$HS" "${SET[@]}" --threads 1 --out "$WORK/s1"
expect 0 "10 cases" -- "$VIADUCT" sweep "$HS" "${SET[@]}" --threads 2 --out "$WORK/s2"
expect 0 "variant,train,speed_kmh,station,max_abs_acc_mps2,max_abs_disp_m" -- head -1 "$WORK/s1/envelope.csv"
expect 0 "reference,HSLM-A9,210,mid," -- cat "$WORK/s1/envelope.csv"
expect 0 "" -- cmp "$WORK/s1/envelope.csv" "$WORK/s2/envelope.csv"
expect 0 "n_failed = 0" -- cat "$WORK/s2/manifest.toml"
expect 0 "11" -- wc -l "$WORK/s1/envelope.csv"
# A rail station along the approach track (track model).
OG=$SRC/scenarios/old-guadiana-talgo.toml
expect 0 "wrote" -- "$VIADUCT" run "$OG" --set 'stations[3].track_x=-5.0' --set 'stations[3].name="approach"' --out "$WORK/og" --speed-kmh 200
expect 0 "approach_rail_disp_m,approach_rail_acc_mps2,approach_rail_acc_filt_mps2" -- head -1 "$WORK/og/history.csv"
# The plot scripts draw what the commands wrote.
expect 0 "envelope.png" -- /usr/bin/python3 "$SRC/scripts/plot_envelope.py" "$WORK/s1"
expect 0 "envelope_disp.png" -- /usr/bin/python3 "$SRC/scripts/plot_envelope.py" "$WORK/s1" --quantity disp
expect 0 "history.png" -- /usr/bin/python3 "$SRC/scripts/plot_history.py" "$WORK/og"
expect 0 "" -- test -s "$WORK/og/history.png"
expect 1 "not found" -- /usr/bin/python3 "$SRC/scripts/plot_envelope.py" "$WORK/nothing"
finish
