#!/usr/bin/env bash
# Issue #39: field records as they come. Bad samples belong to their channel, offsets are removed
# or flagged, geophone channels compare with the model's velocity, the speed comes from the
# train's geometry alone, and a model that does not match the record is flagged. Every case is
# a file a user could have, and each check compares a number with what it must be.
. "$(dirname "$0")/lib.sh"
OG=$SRC/scenarios/old-guadiana-talgo.toml
HS=$SRC/scenarios/hslm-simply-supported.toml
REC=$SRC/data/records/synthetic-deck.csv

# A column of a CSV (by name, '#' lines skipped) at its first data row.
cell() {  # FILE COLUMN
  awk -F, -v c="$2" '/^#/{next} !k{for(i=1;i<=NF;i++) if($i==c) k=i; next} {print $k; exit}' "$1"
}
within() {  # VALUE LOW HIGH WHAT
  if awk -v a="$1" -v l="$2" -v h="$3" 'BEGIN{exit !(a >= l && a <= h)}'; then n_pass=$((n_pass + 1)); else
    echo "FAIL: $4: $1 not in [$2, $3]"; n_fail=$((n_fail + 1)); fi
}

# 1. A 0.3 s NaN run in the acceleration channel: the deflection keeps the whole passage.
awk -F, 'BEGIN{OFS=","} /^#/ || /^t_s/ {print; next} {if ($1+0 > 0.5 && $1+0 < 0.8) $3 = "NaN"; print}' "$REC" > "$WORK/nan-acc.csv"
expect 0 "the other channels keep theirs" -- "$VIADUCT" compare "$OG" --record "$WORK/nan-acc.csv" --map deck_disp=S1_mid --out "$WORK/c1"
within "$(cell "$WORK/c1/compare_metrics.csv" peak_ratio)" 0.999 1.001 "deflection peak ratio with a NaN run in another channel (was 2.95)"
# ... and in the deflection itself, inside the passage: refused, naming channel and span.
awk -F, 'BEGIN{OFS=","} /^#/ || /^t_s/ {print; next} {if ($1+0 > 0.5 && $1+0 < 0.8) $2 = "NaN"; print}' "$REC" > "$WORK/nan-disp.csv"
expect 2 "channel deck_disp_m: the record covers t = 0.8 to 6.016 s" -- "$VIADUCT" compare "$OG" --record "$WORK/nan-disp.csv" \
  --map deck_disp=S1_mid --out "$WORK/o"
# inspect names the channel's missing span; a channel held at its limit counts as missing.
expect 0 "deck_disp_m has no value from 0.502 to 0.798 s" -- "$VIADUCT" inspect "$WORK/nan-disp.csv" --out "$WORK/i"

# 2. A deflection gauge's zero offset (0.2 mm, 18 % of the peak): flagged; --zero removes it.
awk -F, 'BEGIN{OFS=","} /^#/ || /^t_s/ {print; next} {$2 = $2 + 0.0002; print}' "$REC" > "$WORK/offset.csv"
expect 0 "its mean before the train's entry (t = 0 to" -- "$VIADUCT" compare "$OG" --record "$WORK/offset.csv" --map deck_disp=S1_mid --out "$WORK/c2"
expect 0 "a zero offset?" -- grep -F "zero offset" "$WORK/c2/manifest.toml"
expect 0 "" -- "$VIADUCT" compare "$OG" --record "$WORK/offset.csv" --map deck_disp=S1_mid --zero pre-entry --out "$WORK/c3"
within "$(cell "$WORK/c3/compare_metrics.csv" peak_ratio)" 0.995 1.005 "peak ratio with --zero pre-entry"
within "$(cell "$WORK/c3/compare_metrics.csv" zero_removed)" 0.000199 0.000201 "zero removed [m]"
expect 0 "" -- "$VIADUCT" compare "$OG" --record "$WORK/offset.csv" --map deck_disp=S1_mid --zero 0:0.3 --out "$WORK/c4"
within "$(cell "$WORK/c4/compare_metrics.csv" peak_ratio)" 0.995 1.005 "peak ratio with --zero 0:0.3"
expect 2 "too few for its zero" -- "$VIADUCT" compare "$OG" --record "$WORK/offset.csv" --map deck_disp=S1_mid --zero 0:0.01 --out "$WORK/o"
expect 2 "is not pre-entry, keep or START:END" -- "$VIADUCT" compare "$OG" --record "$WORK/offset.csv" --map deck_disp=S1_mid --zero before --out "$WORK/o"

# 3. A passage with the same kind of offset: not judged within (residual "offset"), or zeroed.
PS=$SRC/data/records/passages
awk -F, 'BEGIN{OFS=","} /^#/ || /^t_s/ {print; next} {$3 = $3 + 0.0005; print}' "$PS/passage-01.csv" > "$WORK/p-offset.csv"
printf 'file,train,speed_kmh\np-offset.csv,HSLM-A1,\n' > "$WORK/passages.csv"
expect 0 "a zero offset?" -- "$VIADUCT" passages "$HS" --records "$WORK/passages.csv" --map mid_disp=mid --set analysis.method=modal \
  --set sweep.speed_step_kmh=20 --out "$WORK/p1"
expect 0 ",false,offset," -- grep -F "mid_disp_m" "$WORK/p1/passages.csv"
expect 0 "" -- "$VIADUCT" passages "$HS" --records "$WORK/passages.csv" --map mid_disp=mid --set analysis.method=modal \
  --set sweep.speed_step_kmh=20 --zero pre-entry --out "$WORK/p2"
expect 0 ",true,white," -- grep -F "mid_disp_m" "$WORK/p2/passages.csv"

# 4. A geophone (mm/s) against the model's velocity: the record is the deflection differentiated
# by hand (central differences, independent of the model's integrated acceleration).
expect 0 "" -- "$VIADUCT" run "$HS" --speed-kmh 200 --train HSLM-A1 --out "$WORK/run" --quiet
awk -F, 'NR==1{for(i=1;i<=NF;i++) if($i=="mid_disp_m") k=i; print "t_s,mid_vel [mm/s]"; next}
         {t[NR]=$1; d[NR]=$k} END{for(n=3;n<NR;n++) printf "%.6f,%.9g\n", t[n], 1000*(d[n+1]-d[n-1])/(t[n+1]-t[n-1])}' \
  "$WORK/run/history.csv" > "$WORK/geophone.csv"
expect 0 "" -- "$VIADUCT" compare "$HS" --record "$WORK/geophone.csv" --map mid_vel=mid --speed-kmh 200 --train HSLM-A1 --out "$WORK/v"
within "$(cell "$WORK/v/compare_metrics.csv" peak_ratio)" 0.99 1.01 "geophone peak ratio against the model's velocity"
within "$(cell "$WORK/v/compare_metrics.csv" correlation)" 0.999 1.001 "geophone correlation"

# fit: the offset record gives a biased EI (7.64e9 for 7.694e9, its standard error 0.16 %) with a
# warning; --zero pre-entry recovers it. The geophone fits EI too. (1 s of quiet record first.)
awk -F, 'NR==1{for(i=1;i<=NF;i++) if($i=="mid_disp_m") k=i; print "t_s,mid_disp_m"; for(j=0;j<1000;j++) printf "%.6f,0.0005\n", j/1000; next}
         {printf "%.6f,%.9g\n", $1 + 1.0, $k + 0.0005}' "$WORK/run/history.csv" > "$WORK/fit-offset.csv"
FIT=(--train HSLM-A1 --speed-kmh 200 --param bridge.EI=5e9:1.2e10 --set bridge.EI=7e9)
expect 0 "a zero offset?" -- "$VIADUCT" fit "$HS" --record "$WORK/fit-offset.csv" --map mid_disp=mid "${FIT[@]}" --out "$WORK/f1"
expect 0 "" -- "$VIADUCT" fit "$HS" --record "$WORK/fit-offset.csv" --map mid_disp=mid "${FIT[@]}" --zero pre-entry --out "$WORK/f2"
within "$(awk -F, '$1=="bridge.EI"{print $7}' "$WORK/f2/fit.csv")" 7.69e9 7.70e9 "EI fitted with --zero pre-entry [N m2]"
expect 0 "" -- "$VIADUCT" fit "$HS" --record "$WORK/geophone.csv" --map mid_vel=mid "${FIT[@]}" --out "$WORK/f3"
within "$(awk -F, '$1=="bridge.EI"{print $7}' "$WORK/f3/fit.csv")" 7.66e9 7.73e9 "EI fitted on the geophone [N m2]"

# 5. Speed from the train alone (no model), then with a model whose span is wrong.
awk -F, 'NR==1{for(i=1;i<=NF;i++) if($i=="mid_disp_m") k=i; print "t_s,mid_disp_m"; next}
         {srand(NR); printf "%.6f,%.9g\n", $1 + 2.0, $k + 0.0002 * (rand() - 0.5)}' "$WORK/run/history.csv" > "$WORK/gauge.csv"
expect 0 "train-geometry" -- "$VIADUCT" speed "$WORK/gauge.csv" --channel mid_disp --train hslm:A1 --v-min-kmh 150 --v-max-kmh 260 --out "$WORK/s1"
v=$(cell "$WORK/s1/speed.csv" speed_kmh); u=$(cell "$WORK/s1/speed.csv" uncertainty_kmh)
within "$(awk -v v="$v" -v u="$u" 'BEGIN{d=v-200; print (d<0?-d:d) - u}')" -1e9 0 "train-geometry: |error| within its uncertainty ($v +- $u km/h)"
within "$v" 199 201 "train-geometry speed [km/h] (0.5 %)"
sed "s/^span_lengths = \[15.0\]/span_lengths = [18.0]/; s|\"\.\./data/|\"$SRC/data/|g" "$HS" > "$WORK/long-span.toml"
expect 0 "x the model: check the model" -- "$VIADUCT" speed "$WORK/gauge.csv" --channel mid_disp --model "$WORK/long-span.toml" \
  --station mid --train HSLM-A1 --v-min-kmh 150 --v-max-kmh 260 --out "$WORK/s2"
expect 0 "check the model" -- grep -F "check the model" "$WORK/s2/speed.csv"
within "$(cell "$WORK/s2/speed.csv" uncertainty_kmh)" "$(awk -v v="$(cell "$WORK/s2/speed.csv" speed_kmh)" 'BEGIN{d=v-200; print (d<0?-d:d)}')" 1e9 \
  "the doubted model's uncertainty covers its error [km/h]"
# passages identify speeds with the same checks: the mismatched model's speed flagged, its
# uncertainty covering the truth (was 199.6 +- 0.27 km/h, unflagged). The record padded with 0.5 s
# of noise before and 1 s after, as a logger keeps around a passage.
awk -F, 'NR==2{t0=$1} NR==3{dt=$1-t0} {r[NR]=$0} END{print r[1]; for(j=500;j>=1;j--) printf "%.6f,0\n", t0-j*dt;
         for(i=2;i<=NR;i++) print r[i]; split(r[NR],l,","); for(j=1;j<=1000;j++) printf "%.6f,0\n", l[1]+j*dt}' "$WORK/gauge.csv" > "$WORK/gauge-padded.csv"
printf 'file,train,speed_kmh\ngauge-padded.csv,HSLM-A1,\n' > "$WORK/pass-long.csv"
expect 0 "identified speed: the record is 0.2" -- "$VIADUCT" passages "$WORK/long-span.toml" --records "$WORK/pass-long.csv" --map mid_disp=mid \
  --v-min-kmh 185 --v-max-kmh 215 --set sweep.speed_min_kmh=190 --set sweep.speed_max_kmh=210 --set sweep.speed_step_kmh=10 --out "$WORK/p1"
expect 0 "the uncertainty is widened" -- grep -F "the uncertainty is widened" "$WORK/p1/passages.csv"
within "$(cell "$WORK/p1/passages.csv" speed_uncertainty_kmh)" "$(awk -v v="$(cell "$WORK/p1/passages.csv" speed_kmh)" 'BEGIN{d=v-200; print (d<0?-d:d)}')" 1e9 \
  "passages: the doubted model's uncertainty covers its error [km/h]"
expect 2 "is neither a train file nor hslm:A1" -- "$VIADUCT" speed "$WORK/gauge.csv" --channel mid_disp --train hslm:B2 --out "$WORK/o"

# 6. decay: a failed analysis writes no summary of zeros and says why.
expect 2 "the free vibration sinks into the noise or the record ends after 20.6" -- "$VIADUCT" decay "$REC" --channel deck_acc \
  --frequency-hz 10 --min-cycles 200 --out "$WORK/d"
expect 0 "frequency_hz,,,0" -- cat "$WORK/d/decay_summary.csv"
finish
