#!/usr/bin/env bash
# Issue #36's reproducers: every run that used to exit 0 with a non-physical number now stops with
# a clear message (exit 1 or 2), converges, or is flagged where the number is read.
. "$(dirname "$0")/lib.sh"
HS=$SRC/scenarios/hslm-simply-supported.toml
VS=$SRC/scenarios/vehicles-25m.toml
REC=$SRC/data/records/synthetic-deck.csv
PS=$SRC/data/records/passages

# A number of one column of a CSV file (rows after the header; column by name): the largest |value|.
max_abs() {  # FILE COLUMN
  awk -F, -v c="$2" 'NR==1{for(i=1;i<=NF;i++) if($i==c) k=i; next} /^#/{next} {v=$k<0?-$k:$k; if(v>m) m=v} END{printf "%.9g\n", m}' "$1"
}
# expect_below VALUE LIMIT WHAT
expect_below() {
  if awk -v a="$1" -v b="$2" 'BEGIN{exit !(a < b)}'; then n_pass=$((n_pass + 1)); else
    echo "FAIL: $3: $1 not below $2"; n_fail=$((n_fail + 1)); fi
}

# 1. HHT-alpha as users set it: alpha's own beta and gamma, a bounded answer (was 1.2e24 m).
expect 0 "mid" -- "$VIADUCT" run "$HS" --set analysis.alpha=-0.05 --out "$WORK/hht"
expect_below "$(max_abs "$WORK/hht/history.csv" mid_disp_m)" 0.02 "HHT alpha -0.05 mid-span deflection [m]"
# The sweep's governing acceleration (was 1.4e59 m/s²) against plain Newmark's: within 1 %.
expect 0 "" -- "$VIADUCT" sweep "$HS" --set analysis.alpha=-0.05 --set 'train.files=["hslm:A1"]' --set sweep.speed_step_kmh=20 --out "$WORK/hht-sweep"
expect 0 "" -- "$VIADUCT" sweep "$HS" --set 'train.files=["hslm:A1"]' --set sweep.speed_step_kmh=20 --out "$WORK/nm-sweep"
a_hht=$(max_abs "$WORK/hht-sweep/governing.csv" max_abs_acc_mps2)
a_nm=$(max_abs "$WORK/nm-sweep/governing.csv" max_abs_acc_mps2)
expect_below "$(awk -v a="$a_hht" -v b="$a_nm" 'BEGIN{d=(a-b)/b; print d<0?-d:d}')" 0.01 "HHT against Newmark, governing acceleration (relative)"
expect 2 "key 'analysis.gamma': NewmarkOptions::gamma = 0.5: violated constraint gamma >= 1/2 - alpha = 0.55" -- \
  "$VIADUCT" run "$HS" --set analysis.alpha=-0.05 --set analysis.gamma=0.5 --out "$WORK/o"
expect 2 "key 'analysis.beta'" -- "$VIADUCT" check "$HS" --set analysis.alpha=-0.2 --set analysis.beta=0.25
expect 0 "analysis.beta = 0.35999999" -- "$VIADUCT" check "$HS" --set analysis.alpha=-0.2

# 2. Rigid contact: the same answer at two steps (was 1.3 GN as dt shrank); a landing is refused.
expect 0 "" -- "$VIADUCT" run "$VS" --set train.contact=rigid --out "$WORK/rigid1" --quiet
expect 0 "" -- "$VIADUCT" run "$VS" --set train.contact=rigid --set analysis.dt=0.00025 --out "$WORK/rigid2" --quiet
f1=$(awk -F, 'NR>1{if($5>m)m=$5} END{print m}' "$WORK/rigid1/contact.csv")
f2=$(awk -F, 'NR>1{if($5>m)m=$5} END{print m}' "$WORK/rigid2/contact.csv")
expect_below "$(awk -v a="$f1" -v b="$f2" 'BEGIN{d=(a-b)/b; print d<0?-d:d}')" 0.01 "rigid contact's largest force, 1 ms against 0.25 ms (relative)"
expect_below "$f2" 400000 "rigid contact's largest force [N] (static 152 kN)"
expect 1 "lands on the rail again" -- "$VIADUCT" run "$VS" --set train.contact=rigid --speed-kmh 360 --out "$WORK/o"

# 3. The divergence guard is tested on the kernels (tests/unit/solve/test_newmark.cpp and the
# verification tests); here: a sweep's failing case lands in failures.csv, not in the envelope.

# 4. passages: a deflection record with a 20 mm step is not "within" (its residual says step).
awk -F, 'BEGIN{OFS=","} /^#/ || NR<=5 {print; next} {if ($1+0 > 3.0) $3 = $3 + 0.02; print}' "$PS/passage-01.csv" > "$WORK/step.csv"
printf 'file,train,speed_kmh\nstep.csv,HSLM-A1,\n' > "$WORK/passages.csv"
expect 0 "holds a step of 0.0199" -- "$VIADUCT" passages "$HS" --records "$WORK/passages.csv" --map mid_acc=mid --map mid_disp=mid \
  --set analysis.method=modal --set sweep.speed_step_kmh=20 --out "$WORK/pass"
expect 0 "step" -- grep -F ",false,step," "$WORK/pass/passages.csv"

# 5. Identification without signal: no train found; never a speed outside the range.
awk -F, 'BEGIN{OFS=","} /^#/ || /^t_s/ {print; next} {$2 = 0; $3 = 0.25; print}' "$REC" > "$WORK/flat.csv"
expect 2 "no train found" -- "$VIADUCT" speed "$WORK/flat.csv" --channel deck_acc --distance-m 13.14 --v-min-kmh 100 --v-max-kmh 200 --out "$WORK/o"
expect 2 "no train found" -- "$VIADUCT" speed "$WORK/flat.csv" --channel deck_disp --distance-m 13.14 --peaks --min-interval-s 0.2 --out "$WORK/o"
expect 2 "no train found between 100 and 140 km/h" -- "$VIADUCT" speed "$REC" --channel deck_disp --distance-m 13.14 --peaks \
  --min-interval-s 0.2 --v-min-kmh 100 --v-max-kmh 140 --out "$WORK/o"
expect 0 "" -- "$VIADUCT" speed "$REC" --channel deck_disp --distance-m 13.14 --peaks --min-interval-s 0.2 --v-min-kmh 100 --v-max-kmh 200 --out "$WORK/o"
# compare and passages on an acceleration in g read as m/s² (peak ratio 9.76, correlation 0.9999:
# no word before stop 61), and a deflection in mm read as m; the record as made says nothing.
awk -F, 'BEGIN{OFS=","} /^#/ || /^t_s/ {print; next} {$3 = $3 / 9.80665; $2 = $2 * 1000; print}' "$REC" > "$WORK/units.csv"
expect 0 "times smaller than the model at the peak (9.711 by RMS)" -- "$VIADUCT" compare \
  "$SRC/scenarios/old-guadiana-talgo.toml" --record "$WORK/units.csv" --map deck_acc=S1_mid --map deck_disp=S1_mid --out "$WORK/cu"
expect 0 "the factor between mm and m" -- grep -F "deck_disp_m: the record reads 999.5 times larger" "$WORK/cu/manifest.toml"
expect 1 "" -- sh -c '"$1" compare "$2" --record "$3" --map deck_acc=S1_mid --map deck_disp=S1_mid --out "$4" 2>&1 | grep -q "unit slip"' \
  sh "$VIADUCT" "$SRC/scenarios/old-guadiana-talgo.toml" "$REC" "$WORK/cok"
awk -F, 'BEGIN{OFS=","} /^#/ || /^t_s/ {print; next} {$2 = $2 / 9.80665; print}' "$PS/passage-01.csv" > "$WORK/g.csv"
printf 'file,train,speed_kmh\ng.csv,HSLM-A1,252\n' > "$WORK/g-passages.csv"
expect 0 "the factor between g and m/s². A unit slip?" -- "$VIADUCT" passages "$HS" --records "$WORK/g-passages.csv" \
  --map mid_acc=mid --set analysis.method=modal --set sweep.speed_step_kmh=20 --out "$WORK/pg"
expect 0 ",mid_acc_mps2,mid,acc,mps2," -- grep -F ",false," "$WORK/pg/passages.csv"
# fit against that acceleration in g: named at the initial values (the fit alone said only "ended
# on its upper bound"); the record as simulated says nothing.
expect 0 "" -- "$VIADUCT" run "$HS" --speed-kmh 300 --train HSLM-A1 --out "$WORK/h300" --quiet
awk -F, 'BEGIN{OFS=","} NR==1{for(i=1;i<=NF;i++) if($i=="mid_acc_mps2") k=i; print; next} {$k=$k/9.80665; print}' \
  "$WORK/h300/history.csv" > "$WORK/h300g.csv"
expect 0 "at the initial values: channel mid_acc_mps2: the record reads 9.807 times smaller" -- "$VIADUCT" fit "$HS" \
  --record "$WORK/h300g.csv" --map mid_acc_mps2=mid --train HSLM-A1 --speed-kmh 300 --param bridge.EI=5e9:1e10 --out "$WORK/fg"
expect 0 "the factor between g and m/s²" -- cat "$WORK/fg/fit.toml"
expect 1 "" -- sh -c '"$1" fit "$2" --record "$3" --map mid_acc_mps2=mid --train HSLM-A1 --speed-kmh 300 --param bridge.EI=5e9:1e10 \
  --out "$4" 2>&1 | grep -q "unit slip"' sh "$VIADUCT" "$HS" "$WORK/h300/history.csv" "$WORK/fok"
# fatigue of a strain channel in ε read as µε (damage 0 with no word before), in MPa read as Pa...
awk -F, 'BEGIN{OFS=","} NR<=5 || /^#/ {print; next} {$4 = $4 * 1e-6; print}' "$PS/passage-01.csv" > "$WORK/eps.csv"
expect 0 "channel mid_strain_ue: its largest stress range is 6.303e-05 MPa, below 0.1 MPa" -- "$VIADUCT" fatigue "$WORK/eps.csv" \
  --channel mid_strain --detail 71 --out "$WORK/fe"
expect 0 "quieter than any strain gauge's noise" -- cat "$WORK/fe/manifest.toml"
awk -F, 'BEGIN{OFS=","} NR<=5 || /^#/ {print; next} {$4 = $4 * 1e6; print}' "$PS/passage-01.csv" > "$WORK/ueps.csv"
expect 0 "above 1000 MPa" -- "$VIADUCT" fatigue "$WORK/ueps.csv" --channel mid_strain --detail 71 --out "$WORK/fu"
# ...and a section modulus in cm³ given as m³ for a traffic mix; the record as made says nothing.
expect 0 "mid_moment_Nm over the mix's trains: its largest stress range is" -- "$VIADUCT" fatigue "$HS" --mix \
  "$SRC/data/trains/fatigue/mix-standard.toml" --channel mid_moment --section-modulus-m3 5e4 --detail 71 --out "$WORK/fm"
expect 1 "" -- sh -c '"$1" fatigue "$2" --channel mid_strain --detail 71 --out "$3" 2>&1 | grep -q "stress range is"' \
  sh "$VIADUCT" "$PS/passage-01.csv" "$WORK/fok"
# compare on a record cut inside the passage, and on a stuck channel: refused, naming the spans.
head -n 1000 "$REC" > "$WORK/cut.csv"
expect 2 "the record lost part of the passage" -- "$VIADUCT" compare "$SRC/scenarios/old-guadiana-talgo.toml" --record "$WORK/cut.csv" \
  --map deck_acc=S1_mid --out "$WORK/o"
awk -F, 'BEGIN{OFS=","} /^#/ || /^t_s/ {print; next} {if ($1+0 > 1.0 && $1+0 < 1.3) $3 = 0.125; print}' "$REC" > "$WORK/stuck.csv"
expect 2 "a stuck channel" -- "$VIADUCT" compare "$SRC/scenarios/old-guadiana-talgo.toml" --record "$WORK/stuck.csv" \
  --map deck_acc=S1_mid --out "$WORK/o"

# 6. Plausibility: unit slips and coarse decks warn where the number is read (exit 0, stderr, manifest).
expect 0 "check the unit of bridge.EI (N·m², not kN·m²" -- "$VIADUCT" run "$HS" --set bridge.EI=7.694e6 --out "$WORK/ei"
expect 0 "beyond L/100" -- grep -F "L/100" "$WORK/ei/manifest.toml"
expect 0 "check the unit of bridge.mass_per_m (kg/m, not t/m" -- "$VIADUCT" run "$HS" --set bridge.mass_per_m=15.0 --out "$WORK/o"
expect 0 "bridge.bearings.k (N/m)" -- "$VIADUCT" check "$HS" --set bridge.bearings.rigid=false --set bridge.bearings.k=1e3
# track stiffnesses in kN/m where N/m are asked: the rail 60 mm down and the deck's acceleration
# -63 % (0.19 against 0.52 m/s² on the Talgo run), said once where the track is pressed most
OT=$SRC/scenarios/old-guadiana-talgo.toml
expect 0 "the track at the approach (x = -10 m): the heaviest wheel (112 kN) presses the rail 58.8 mm statically" -- \
  "$VIADUCT" check "$OT" --set track.ballast.k=1.933e5
expect 0 "presses the rail 96.9 mm statically, beyond the 10 mm" -- "$VIADUCT" run "$OT" --set track.pad.k=1e5 --out "$WORK/pad"
expect 0 "(N/m, not kN/m)" -- cat "$WORK/pad/manifest.toml"
expect 1 "" -- sh -c '"$1" check "$2" 2>&1 | grep -q "presses the rail"' sh "$VIADUCT" "$OT"
# damping in percent where a ratio is asked (0.5 for 0.5 %: 2.03 m/s² instead of 72.9 under HSLM-A1)
expect 0 "bridge.damping.ratio = 0.5 (50 % of critical)" -- "$VIADUCT" run "$HS" --set bridge.damping.ratio=0.5 --out "$WORK/z"
expect 0 "the key is a ratio, not a percentage" -- grep -F "of critical" "$WORK/z/manifest.toml"
expect 0 "bridge.damping.ratio2 = 0.2 (20 % of critical)" -- "$VIADUCT" check "$HS" --set 'bridge.damping.kind="rayleigh"' \
  --set bridge.damping.f1_hz=5 --set bridge.damping.f2_hz=20 --set bridge.damping.ratio1=0.02 --set bridge.damping.ratio2=0.2
expect 1 "" -- sh -c '"$1" check "$2" --set bridge.damping.ratio=0.05 2>&1 | grep -q "of critical"' sh "$VIADUCT" "$HS"
# axle loads in tonnes where kN are asked (every response a tenth of the true one); HSLM-A1's are not
printf 'position_m,load_kN\n0,17\n2.5,17\n17.5,17\n20,17\n' > "$WORK/tonnes.csv"
expect 0 "train tonnes: its heaviest axle carries 17 kN, below the 40 kN" -- "$VIADUCT" run "$HS" \
  --set "train.files=[\"$WORK/tonnes.csv\"]" --out "$WORK/t17"
expect 0 "(kN, not t: 17 t is 167 kN)" -- cat "$WORK/t17/manifest.toml"
expect 1 "" -- sh -c '"$1" check "$2" 2>&1 | grep -q "heaviest axle carries"' sh "$VIADUCT" "$HS"
# axle positions in mm where m are asked (a 20 km "train", each axle alone on the span) or in km
printf 'position_m,load_kN\n0,170\n2500,170\n17500,170\n20000,170\n' > "$WORK/mm.csv"
expect 0 "train mm: axles 2 and 3 are 1.5e+04 m apart, beyond the 50 m" -- "$VIADUCT" run "$HS" --set "train.files=[\"$WORK/mm.csv\"]" \
  --out "$WORK/tmm"
expect 0 "check the unit of its positions (m, not mm: a 20 m coach in mm is 20 km long" -- cat "$WORK/tmm/manifest.toml"
printf 'position_m,load_kN\n0,170\n0.0025,170\n0.0175,170\n0.02,170\n' > "$WORK/km.csv"
expect 0 "closer than the 1 m of any two axles" -- "$VIADUCT" check "$HS" --set "train.files=[\"$WORK/km.csv\"]"
expect 1 "" -- sh -c '"$1" check "$2" --set "train.files=[\"$3\"]" 2>&1 | grep -q " apart"' sh "$VIADUCT" "$HS" \
  "$SRC/data/trains/talgo-altaria.csv"
expect 0 "1 element; it needs 4" -- "$VIADUCT" check "$HS" --set bridge.element_size=15
expect 0 "use analysis.method = \"newmark\" below" -- "$VIADUCT" check "$SRC/scenarios/old-guadiana-talgo.toml" \
  --set 'analysis.preset="default"' --set run.speed_kmh=20

# 7. An output directory never shows an earlier run's manifest beside new files.
expect 0 "" -- "$VIADUCT" run "$HS" --out "$WORK/dir" --quiet
cp "$WORK/dir/manifest.toml" "$WORK/old-manifest.toml"
expect 2 "" -- "$VIADUCT" run "$HS" --set analysis.dt=0 --out "$WORK/dir"   # refused before writing: the old run stays whole
expect 0 "" -- cmp "$WORK/dir/manifest.toml" "$WORK/old-manifest.toml"
expect 0 "sha256" -- grep -A1 'file = "history.csv"' "$WORK/dir/manifest.toml"
echo "0.5,0,0" >> "$WORK/dir/history.csv"   # another run's file, or a hand's
expect 1 "changed since the run" -- /usr/bin/python3 "$SRC/scripts/plot/plot_history.py" "$WORK/dir"
rm "$WORK/dir/manifest.toml"                  # a run killed before its manifest
expect 1 "has no manifest.toml" -- /usr/bin/python3 "$SRC/scripts/plot/plot_history.py" "$WORK/dir"

# 8. Input checks: a line break in --set, integers beyond an int.
expect 2 "holds a line break" -- "$VIADUCT" check "$HS" --set $'analysis.dt=0.002\nanalysis.alpha=-0.1'
expect 2 "must be an integer within +-2147483647" -- "$VIADUCT" check "$HS" --set modal.n_modes=1180591620717411303424
awk -F, '/^#/{next} NR>0 && /^t_s/{print "deck_acc_mps2"; next} {print $3}' "$REC" > "$WORK/rate.csv"
# time stamps in ms read as seconds: the rate 0.5 Hz, said with the likely cause before the
# filter refuses it; the same stamps for a deflection log (slow logs exist) say nothing
awk -F, 'BEGIN{OFS=","} /^# sampling_rate/ {next} /^#/ || /^t_s/ {print; next} {$1 = $1 * 1000; print}' "$REC" > "$WORK/ms.csv"
expect 2 "are they milliseconds? name the column t_ms" -- "$VIADUCT" compare "$SRC/scenarios/old-guadiana-talgo.toml" \
  --record "$WORK/ms.csv" --map deck_acc=S1_mid --out "$WORK/o"
awk -F, 'BEGIN{OFS=","} /^#/ {print; next} /^t_s/ {print "t_s,deck_disp_m"; next} {print $1, $2}' "$WORK/ms.csv" > "$WORK/ms-disp.csv"
expect 1 "" -- sh -c '"$1" inspect "$2" --out "$3" 2>&1 | grep -q milliseconds' sh "$VIADUCT" "$WORK/ms-disp.csv" "$WORK/o"
expect 2 "check the record's sampling rate" -- "$VIADUCT" compare "$SRC/scenarios/old-guadiana-talgo.toml" --record "$WORK/rate.csv" \
  --rate-hz 1e9 --time-column none --map deck_acc=S1_mid --out "$WORK/o"
finish
