#!/usr/bin/env bash
# viaduct fatigue (issue #42, first part): rainflow cycles and Miner damage of a record's stress,
# strain or moment channels against EN 1993-1-9's curves; the realistic mistakes refused.
. "$(dirname "$0")/lib.sh"

cell() {  # FILE COLUMN: the first data row's value
  awk -F, -v c="$2" '!k{for(i=1;i<=NF;i++) if($i==c) k=i; next} {print $k; exit}' "$1"
}
within() {  # VALUE LOW HIGH WHAT
  if awk -v a="$1" -v l="$2" -v h="$3" 'BEGIN{exit !(a >= l && a <= h)}'; then n_pass=$((n_pass + 1)); else
    echo "FAIL: $4: $1 not in [$2, $3]"; n_fail=$((n_fail + 1)); fi
}

# A sine of 1000 periods, range 84 MPa, written as a stress, a strain (400 µε on steel) and a
# moment (42 kN m amplitude over W = 1e-3 m3), in a logger's units (MPa, µε, kN·m). Rainflow: 999.5 cycles of 84 MPa and two halves of 42 MPa.
awk 'BEGIN{print "t_s,s [MPa],e [µε],m [kN·m],a [m/s^2]"; for(k=0;k<=20000;k++){x=sin(2*3.141592653589793*k/20);
     printf "%.4f,%.12g,%.12g,%.12g,%.12g\n", k/1000, 42*x, 200*x, 42*x, x}}' > "$WORK/sine.csv"
D=$(awk 'BEGIN{dd=71*exp(log(0.4)/3); print 999.5/(2e6*(71/84)^3) + 1/(5e6*(dd/42)^5)}')
expect 0 "" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel s --detail 71 --out "$WORK/f1"
within "$(cell "$WORK/f1/damage.csv" damage)" "$(awk -v d="$D" 'BEGIN{print d*(1-1e-6)}')" "$(awk -v d="$D" 'BEGIN{print d*(1+1e-6)}')" \
  "stress channel: D against n/N by hand ($D)"
within "$(cell "$WORK/f1/damage.csv" cycles)" 1000.5 1000.5 "cycles counted"
expect 0 "" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel e --detail 71 --out "$WORK/f2"
within "$(cell "$WORK/f2/damage.csv" damage)" "$(awk -v d="$D" 'BEGIN{print d*(1-1e-6)}')" "$(awk -v d="$D" 'BEGIN{print d*(1+1e-6)}')" \
  "strain channel x E (210 GPa)"
expect 0 "" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel m --detail 71 --section-modulus-m3 1e-3 --method four-point --out "$WORK/f3"
within "$(cell "$WORK/f3/damage.csv" damage)" "$(awk -v d="$D" 'BEGIN{print d*(1-1e-6)}')" "$(awk -v d="$D" 'BEGIN{print d*(1+1e-6)}')" \
  "moment channel / W, four-point"
# The range-mean matrix holds every count.
within "$(awk -F, 'NR>1{s+=$6} END{print s}' "$WORK/f1/cycles.csv")" 1000.5 1000.5 "cycles.csv sums to the count"
# A user curve equal to category 71's gives its damage; gamma_Mf = 1.35 raises it (m = 3: x 1.35^3 on the big cycles).
expect 0 "" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel s --delta-c-mpa 71 --out "$WORK/f4"
within "$(cell "$WORK/f4/damage.csv" damage)" "$(awk -v d="$D" 'BEGIN{print d*(1-1e-6)}')" "$(awk -v d="$D" 'BEGIN{print d*(1+1e-6)}')" \
  "user curve 71/3/5 = category 71"
expect 0 "" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel s --detail 71 --gamma-mf 1.35 --out "$WORK/f5"
within "$(cell "$WORK/f5/damage.csv" damage)" "$(awk -v d="$D" 'BEGIN{print d*2.4}')" 1 "gamma_Mf 1.35"

# A simulated history: Annex D's Type 1 train over the 15 m span at 20 km/h. The quasi-static
# mid-span moment's largest rainflow range is its peak (the history starts and ends at 0), and
# that peak is the influence line's by hand (an axle at mid-span; 0.2 %: the FE moment at a node
# with an axle inside the next 0.5 m element is recovered from the element's end forces).
expect 0 "" -- "$VIADUCT" run "$SRC/scenarios/hslm-simply-supported.toml" --set 'train.files=["'"$SRC"'/data/trains/fatigue/type1.csv"]' \
  --speed-kmh 20 --set 'analysis.method="modal"' --out "$WORK/t1" --quiet
expect 0 "" -- "$VIADUCT" fatigue "$WORK/t1/quasi_static.csv" --channel mid_moment --detail 71 --section-modulus-m3 0.05 --out "$WORK/f6"
hand=$(awk -F, '/^#/||/^position/{next} {x[n]=$1; p[n]=$2*1e3; n++}
  END{L=15; best=0; for(i=0;i<n;i++){h=x[i]+L/2; m=0; for(j=0;j<n;j++){s=h-x[j]; if(s>0&&s<L) m+=p[j]*(s<=L/2? s/2 : (L-s)/2)} if(m>best) best=m}
      print best/0.05*1e-6}' "$SRC/data/trains/fatigue/type1.csv")
within "$(cell "$WORK/f6/damage.csv" max_range_mpa)" "$(awk -v h="$hand" 'BEGIN{print h*0.998}')" "$(awk -v h="$hand" 'BEGIN{print h*1.002}')" \
  "Type 1 over 15 m: largest range against the influence line by hand ($hand MPa)"
within "$(cell "$WORK/f6/damage.csv" max_range_mpa)" "$(awk -F, 'NR>1&&$3>m{m=$3} END{print m/0.05*1e-6*(1-1e-7)}' "$WORK/t1/quasi_static.csv")" \
  "$(awk -F, 'NR>1&&$3>m{m=$3} END{print m/0.05*1e-6*(1+1e-7)}' "$WORK/t1/quasi_static.csv")" "largest range = the history's peak"

# A run of NaN in the strain channel (a logger dropout) cuts that channel only: the stress
# channel's damage is the whole record's.
awk -F, 'NR>1 && NR>=5000 && NR<5300 {$3="NaN"} {print}' OFS=, "$WORK/sine.csv" > "$WORK/gap.csv"
expect 0 "" -- "$VIADUCT" fatigue "$WORK/gap.csv" --channel s --channel e --detail 71 --out "$WORK/f7"
within "$(cell "$WORK/f7/damage.csv" damage)" "$(awk -v d="$D" 'BEGIN{print d*(1-1e-6)}')" "$(awk -v d="$D" 'BEGIN{print d*(1+1e-6)}')" \
  "a NaN run in another channel leaves the stress channel's damage whole"

# A traffic mix (--mix): two of Annex D's trains over the 15 m span, the mid-span moment. Each
# train's damage a year is its passage's x its trains a day x 365, the total their sum, and a
# train's passage is what `fatigue` counts on that train's own run at its speed (1e-4: history.csv
# holds the moment to 10 significant digits).
printf 'title = "two trains"\n[[trains]]\nfile = "%s"\nper_day = 3\nspeed_kmh = 120\n[[trains]]\nfile = "%s"\nper_day = 2.5\nspeed_kmh = 100\n' \
  "$SRC/data/trains/fatigue/type9.csv" "$SRC/data/trains/fatigue/type10.csv" > "$WORK/mix.toml"
SPAN=("$SRC/scenarios/hslm-simply-supported.toml" --set 'analysis.method="modal"')
expect 0 "two trains at mid_moment_Nm: D = " -- "$VIADUCT" fatigue "${SPAN[@]}" --mix "$WORK/mix.toml" --channel mid_moment \
  --section-modulus-m3 0.01 --detail 71 --threads 2 --out "$WORK/mix"
within "$(awk -F, 'NR==1{for(i=1;i<=NF;i++) c[$i]=i; next} $1!="total"{s+=$c["damage_per_year"]} $1=="total"{t=$c["damage_per_year"]}
  END{print s/t}' "$WORK/mix/damage.csv")" 0.999999 1.000001 "the mix's damage a year is the trains' sum"
within "$(awk -F, 'NR==1{for(i=1;i<=NF;i++) c[$i]=i; next} $1=="type9"{print $c["damage_per_year"]/($c["damage_per_passage"]*3*365)}' "$WORK/mix/damage.csv")" \
  0.999999 1.000001 "a train's damage a year: its passage's x 3 a day x 365"
expect 0 "" -- "$VIADUCT" run "${SPAN[@]}" --set 'train.files=["'"$SRC"'/data/trains/fatigue/type9.csv"]' --speed-kmh 120 --out "$WORK/t9" --quiet
expect 0 "" -- "$VIADUCT" fatigue "$WORK/t9/history.csv" --channel mid_moment --detail 71 --section-modulus-m3 0.01 --out "$WORK/f9" --quiet
within "$(awk -F, -v d="$(cell "$WORK/f9/damage.csv" damage)" 'NR==1{for(i=1;i<=NF;i++) c[$i]=i; next} $1=="type9"{print $c["damage_per_passage"]/d}' \
  "$WORK/mix/damage.csv")" 0.9999 1.0001 "type 9's passage in the mix = fatigue on its own run"
# A title with a quote and a line break (the user's text) leaves a manifest that reads.
sed 's/^title = .*/title = "two \\"quoted\\"\\ntrains"/' "$WORK/mix.toml" > "$WORK/mix-title.toml"
expect 0 "" -- "$VIADUCT" fatigue "${SPAN[@]}" --mix "$WORK/mix-title.toml" --channel mid_moment --section-modulus-m3 0.01 --detail 71 -q --out "$WORK/mixt"
expect 0 'two "quoted"' -- /usr/bin/python3 -c 'import sys, tomllib; print(tomllib.load(open(sys.argv[1], "rb"))["run"]["mix"])' "$WORK/mixt/manifest.toml"
sed 's/type10.csv/type13.csv/' "$WORK/mix.toml" > "$WORK/mix-bad.toml"
expect 2 "mix-bad.toml:7: key 'trains[1].file': no train file" -- "$VIADUCT" fatigue "${SPAN[@]}" --mix "$WORK/mix-bad.toml" --channel mid_moment --detail 71 --section-modulus-m3 0.01 --out "$WORK/o"
expect 2 "channel mid_shear: the scenario has no such load effect; fatigue takes mid_moment" -- "$VIADUCT" fatigue "${SPAN[@]}" \
  --mix "$WORK/mix.toml" --channel mid_shear --detail 71 --out "$WORK/o"
expect 2 "--mix: give one --channel" -- "$VIADUCT" fatigue "${SPAN[@]}" --mix "$WORK/mix.toml" --detail 71 --out "$WORK/o"

# Mistakes: a moment without W, an acceleration, an unknown category, two curves, no curve.
expect 2 "is a moment [N m]: give --section-modulus-m3" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel m --detail 71 --out "$WORK/o"
expect 2 "channel a_mps2 is in mps2: fatigue needs a stress" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel s --channel a --detail 71 --out "$WORK/o"
expect 2 "detail category 75 is not one of EN 1993-1-9's: 36, 40" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel s --detail 75 --out "$WORK/o"
expect 2 "give exactly one of --detail" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel s --detail 71 --delta-c-mpa 71 --out "$WORK/o"
expect 2 "give exactly one of --detail" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel s --out "$WORK/o"
expect 2 "--range-bin-mpa = -1: violated constraint > 0" -- "$VIADUCT" fatigue "$WORK/sine.csv" --channel s --detail 71 --range-bin-mpa -1 --out "$WORK/o"
finish
