#!/usr/bin/env bash
# Bad input: exit code 2 with file, line and key; never a crash.
. "$(dirname "$0")/lib.sh"
OG=$SRC/scenarios/old-guadiana-sensitivity.toml
mkdir -p "$WORK/parts"
cat > "$WORK/parts/bridge.toml" <<'T'
span_lengths = [10.0]
EI = 2e9
mass_per_m = 5000.0
T
cat > "$WORK/parts/train.toml" <<'T'
kind = "regular"
n_axles = 2
spacing = 10.0
axle_load_kN = 100
T
scen() {  # scen NAME EXTRA: writes a small scenario with EXTRA appended
  printf '[bridge]\nfile = "parts/bridge.toml"\n[train]\nfiles = ["parts/train.toml"]\n[[stations]]\nname = "mid"\nspan = 1\nat = 0.5\n%b' "$2" > "$WORK/$1.toml"
  echo "$WORK/$1.toml"
}

expect 0 "model" -- "$VIADUCT" check "$(scen ok '')"
expect 2 "unknown.toml:10: key 'analysis.dtt': unknown key (did you mean 'analysis.dt'?)" -- "$VIADUCT" check "$(scen unknown '[analysis]\ndtt = 1e-3\n')"
expect 2 "wrongtype.toml:10: key 'analysis.dt': must be a number" -- "$VIADUCT" check "$(scen wrongtype '[analysis]\ndt = "small"\n')"
expect 2 "key 'analysis.dt': must be > 0 [s], got 0" -- "$VIADUCT" run "$(scen dt0 '[analysis]\ndt = 0.0\n')" --speed-kmh 100 --out "$WORK/o"
expect 2 "key 'analysis.dt': must be > 0 [s], got -0.001" -- "$VIADUCT" check "$(scen dtneg '[analysis]\ndt = -1e-3\n')"
# A filter option that breaks its rule is reported against its own key (was filter.high_hz).
expect 2 "order13.toml:10: key 'filter.order': Cheby1Spec::order = 13: violated constraint order in 1..12" -- "$VIADUCT" check "$(scen order13 '[filter]\norder = 13\n')"
expect 2 "key 'track.pad.k': must be > 0 [N/m], got -100000000" -- "$VIADUCT" check "$OG" --set track.pad.k=-1e8
expect 2 "--set: key 'bridge.bearings.k': must be >= 0 [N/m], got -5" -- "$VIADUCT" check "$OG" --set bridge.bearings.k=-5.0
printf 'span_lengths = [10.0]\nEI = -2e9\nmass_per_m = 5000.0\n' > "$WORK/parts/negEI.toml"
expect 2 "negEI.toml:2: key 'bridge.EI': must be > 0 [N·m²], got -2000000000" -- "$VIADUCT" check "$(scen negei '')" --set "bridge.file=$WORK/parts/negEI.toml"
expect 2 "key 'bridge.span_lengths': must be > 0 [m], got 0" -- "$VIADUCT" check "$OG" --set "bridge.span_lengths=[0.0, 11.93]"
expect 2 "key 'run.speed_kmh': must be > 0 [km/h], got 0" -- "$VIADUCT" run "$(scen speed0 '[run]\nspeed_kmh = 0.0\n')"
expect 2 "--speed-kmh must be > 0" -- "$VIADUCT" run "$(scen speedneg '')" --speed-kmh -10 --out "$WORK/o"
expect 2 "key 'sweep.speeds_kmh': must be > 0 [km/h], got -50" -- "$VIADUCT" sweep "$(scen sweepneg '[sweep]\nspeeds_kmh = [100, -50]\n')" --out "$WORK/o"
expect 2 "train file not found" -- "$VIADUCT" check "$(scen notrain '')" --set 'train.files=["parts/nope.toml"]'
printf 'position_m,load_kN\n0,100\n3.0,x\n' > "$WORK/parts/bad.csv"
expect 2 "bad.csv:3: not a number" -- "$VIADUCT" check "$(scen badcsv '')" --set "train.files=[\"$WORK/parts/bad.csv\"]"
printf 'kind = "regular"\nn_axles = 2\nspacing = 10.0\naxle_load = 100\n' > "$WORK/parts/badkey.toml"
expect 2 "badkey.toml:4: key 'axle_load': unknown train key" -- "$VIADUCT" check "$(scen badkey '')" --set "train.files=[\"$WORK/parts/badkey.toml\"]"
printf '[bridge\nfile = 3\n' > "$WORK/syntax.toml"
expect 2 "TOML syntax error" -- "$VIADUCT" check "$WORK/syntax.toml"
expect 2 "file not found" -- "$VIADUCT" check "$WORK/absent.toml"
expect 2 "unknown key (did you mean 'track.pad.k'?)" -- "$VIADUCT" check "$OG" --set track.pad.kk=1
expect 2 "SCENARIO is required" -- "$VIADUCT" run
expect 2 "unrecognised option" -- "$VIADUCT" run "$OG" --speeed 3
expect 2 "unknown command 'frobnicate'" -- "$VIADUCT" frobnicate
expect 2 "--threads must be >= 0" -- "$VIADUCT" sweep "$OG" --threads -2
expect 2 "no speeds" -- "$VIADUCT" sweep "$(scen nospeeds '')" --out "$WORK/o"
expect 2 "no speed: give --speed-kmh" -- "$VIADUCT" run "$(scen nospeed '')" --out "$WORK/o"
expect 2 "no train named 'TGV'" -- "$VIADUCT" run "$OG" --speed-kmh 100 --train TGV --out "$WORK/o"
expect 2 "key 'stations[0].at': must be [0, 1], got 1.5" -- "$VIADUCT" run "$(scen far '')" --set stations[0].at=1.5 --speed-kmh 100 --out "$WORK/o"
expect 2 "a deck station needs exactly one of 'at' (fraction), 'x' (metres) or 'every_m' (stations along the span)" -- "$VIADUCT" run "$(scen both '')" --set stations[0].x=3.0 --speed-kmh 100 --out "$WORK/o"
# Stations along a span: not with at or x, not on the track, not a million of them, no name twice.
expect 2 "a deck station needs exactly one of 'at' (fraction), 'x' (metres) or 'every_m'" -- "$VIADUCT" check "$(scen alongat '')" --set stations[0].every_m=0.5
expect 2 "key 'stations[0].every_m': stations along a span give load effects only: add a station with 'at', 'x' or 'track_x'" -- "$VIADUCT" check "$(scen alongonly '')" --unset stations[0].at --set stations[0].every_m=1.0
# Without --load-effects a sweep keeps nothing of them: said, with the key, not dropped silently.
expect 0 "key 'stations[1].every_m': stations along a span give load effects only, which this sweep does not keep" -- "$VIADUCT" sweep "$(scen alongnoeff '[[stations]]\nname = "L"\nspan = 1\nevery_m = 2.0\n[sweep]\nspeeds_kmh = [100]\n')" --out "$WORK/along-noeff"
expect 2 "key 'stations[0].every_m': would place" -- "$VIADUCT" check "$(scen alongmany '')" --unset stations[0].at --set stations[0].every_m=1e-5
expect 2 "key 'stations[0].every_m': must be > 0 [m], got 0" -- "$VIADUCT" check "$(scen along0 '')" --unset stations[0].at --set stations[0].every_m=0.0
expect 2 "alongdup.toml:10: key 'stations[1].name': station 'm_0.00m' (along the span) repeats a station name" -- "$VIADUCT" check "$(scen alongdup '[[stations]]\nname = "m"\nspan = 1\nevery_m = 1.0\n')" --set 'stations[0].name="m_0.00m"'
# Records: bad files exit 2 with file, line and column.
printf 't_s,a_mps2\n0,1\n0.01,NaN\n' > "$WORK/nan.csv"
expect 2 "no 2 successive samples in which every channel used has a value (missing: a_mps2 from 0.01" -- "$VIADUCT" filter "$WORK/nan.csv"
printf 't_s,a_mps2\n0,1\n0.01,NaN\n0.02,1\n0.03,1\n' > "$WORK/nan-refused.csv"
expect 2 "nan-refused.csv:3: missing samples too long to interpolate (--fill-max-s 0 s) or at an end: a_mps2, 1 samples from 0.01 to 0.01 s" -- "$VIADUCT" filter "$WORK/nan-refused.csv" --fill-max-s 0 --long-gaps refuse
expect 2 "--long-gaps must be split or refuse" -- "$VIADUCT" filter "$WORK/nan-refused.csv" --long-gaps drop
expect 2 "--fill-max-s must be" -- "$VIADUCT" filter "$WORK/nan-refused.csv" --fill-max-s -1
expect 2 "--unit needs CHANNEL=UNIT" -- "$VIADUCT" filter "$WORK/nan-refused.csv" --unit a_mps2
expect 2 "--unit b=g: no such column in the header" -- "$VIADUCT" filter "$WORK/nan-refused.csv" --unit b=g
# fit reads logger files as the record commands do, and says what it converted.
expect 2 "viaduct fit: $SRC/data/records/logger-semicolon.csv: 'Acc S1 mid [g]' -> Acc_S1_mid_mps2 (x 9.80665)" -- "$VIADUCT" fit "$OG" \
  --record "$SRC/data/records/logger-semicolon.csv" --map 'Nope=S1_mid' --param bridge.EI=5e9:1e10 --out "$WORK/o"
# A record written from printf's FORMAT and the error a command must give for it:
# bad_record FILE FORMAT COMMAND MESSAGE
bad_record() { printf "$2" > "$WORK/$1"; expect 2 "$4" -- "$VIADUCT" "$3" "$WORK/$1"; }
bad_record allnan.csv 't_s,a_mps2\nNaN,1\nNaN,1\n' inspect "allnan.csv:2: no time stamp in column 't_s'"
bad_record back.csv 't_s,a_mps2\n0,1\n0.01,2\n0.005,3\n' spectrum "back.csv:4: time does not increase (t = 0.005 s after 0.01 s on line 3)"
bad_record empty.csv '' spectrum "no header line"
bad_record cols.csv 't_s,a_mps2,b_mps2\n0,1,2\n0.01,2\n' filter "cols.csv:3: expected 3 columns as in the header (line 1), got 2"
bad_record jitter.csv 't_s,a_mps2\n0,1\n0.01,2\n0.02,3\n0.035,4\n0.045,5\n' spectrum \
  "jitter.csv:5: irregular sampling: a step of 0.015 s where the others are 0.01 s (1.5 samples)"
bad_record unit.csv 't_s,a_furlongs\n0,1\n0.01,2\n' spectrum \
  "unit.csv:1: channel 'a_furlongs' has no unit: name it a_furlongs_<unit> or 'a_furlongs [unit]', or give --unit 'a_furlongs=UNIT'"
expect 2 "synthetic-deck.csv: Chebyshev filter: --high-hz = 300: violated constraint high_hz in (0, fs/2 = 250) Hz" -- "$VIADUCT" filter "$SRC/data/records/synthetic-deck.csv" --high-hz 300
expect 2 "synthetic-deck.csv: Welch: --nperseg = 100000: violated constraint nperseg <= the record's 3009 samples" -- "$VIADUCT" spectrum "$SRC/data/records/synthetic-deck.csv" --welch --nperseg 100000
expect 2 "no channel 'rail'" -- "$VIADUCT" spectrum "$SRC/data/records/synthetic-deck.csv" --channel rail
expect 2 "RECORD is required" -- "$VIADUCT" spectrum
expect 2 "--set and --unset change scenario keys; viaduct filter takes no scenario" -- "$VIADUCT" filter "$SRC/data/records/synthetic-deck.csv" --set filter.high_hz=20

# compare: missing or wrong mappings
TALGO=$SRC/scenarios/old-guadiana-talgo.toml
REC=$SRC/data/records/synthetic-deck.csv
expect 2 "--record FILE is required" -- "$VIADUCT" compare "$TALGO" --map deck_acc=S1_mid
expect 2 "at least one --map" -- "$VIADUCT" compare "$TALGO" --record "$REC"
expect 2 "no station 'S9'" -- "$VIADUCT" compare "$TALGO" --record "$REC" --map deck_acc=S9
expect 2 "no channel 'strain'" -- "$VIADUCT" compare "$TALGO" --record "$REC" --map strain=S1_mid
expect 2 "--map needs CHANNEL=STATION" -- "$VIADUCT" compare "$TALGO" --record "$REC" --map deck_acc
printf '# sampling_rate_hz = 100\nv_V\n1\n2\n3\n' > "$WORK/volts.csv"
expect 2 "channel 'v_V' is in V; only accelerations (_mps2, [g], ...), velocities (_mps, [mm/s], ...), deflections (_m, [mm], ...) and strains (_ue, [µε], ...) compare with the model" -- "$VIADUCT" compare "$TALGO" --record "$WORK/volts.csv" --map v=S1_mid

# Sizes that would exhaust memory or time are refused with the key to change.
expect 2 "key 'bridge.element_size': 1e-06 m gives 11930000 elements on span 1; at most 1000 per span (raise bridge.element_size)" -- "$VIADUCT" check "$OG" --set bridge.element_size=1e-6
expect 2 "key 'track.rail_elements_per_bay': 2000 with sleepers every 0.6 m over 63.86 m of track gives 212000 rail elements; at most 100000" -- "$VIADUCT" check "$OG" --set track.rail_elements_per_bay=2000
expect 2 "key 'track.sleeper_spacing': 500 m is longer than the track (63.86 m)" -- "$VIADUCT" check "$OG" --set track.sleeper_spacing=500
expect 2 "key 'bridge.mass_per_m': plus added_mass_per_m minus the modelled track mass" -- "$VIADUCT" check "$SRC/scenarios/old-guadiana-talgo.toml" --set bridge.mass_per_m=10 --set bridge.mass_includes_track=true
expect 2 "GiB of histories" -- "$VIADUCT" run "$OG" --speed-kmh 0.001 --out "$WORK/o"
expect 2 "the dense eigen solver takes at most 6000 DOFs" -- "$VIADUCT" modes "$OG" --set track.rail_elements_per_bay=40 --out "$WORK/o"

# Solution methods (issue #5): unknown choices and out-of-range tolerances name the key.
expect 2 "key 'analysis.method': must be one of newmark|modal|ida, got 'euler'" -- "$VIADUCT" check "$(scen meth '[analysis]\nmethod = "euler"\n')"
expect 2 "key 'analysis.preset': must be one of |fast|default|reference, got 'turbo'" -- "$VIADUCT" check "$(scen preset '[analysis]\npreset = "turbo"\n')"
expect 2 "key 'ida.rtol': must be [1e-12, 0.1], got 0" -- "$VIADUCT" check "$(scen rtol '[ida]\nrtol = 0.0\n')"
expect 2 "key 'ida.max_order': must be [1, 5], got 7" -- "$VIADUCT" check "$(scen order '[ida]\nmax_order = 7\n')"
expect 2 "key 'modal.max_frequency_hz': must be >= 0 [Hz], got -5" -- "$VIADUCT" check "$(scen fneg '[modal]\nmax_frequency_hz = -5.0\n')"
expect 2 "keeps no mode: the lowest is" -- "$VIADUCT" run "$(scen fmax '[analysis]\nmethod = "modal"\n[modal]\nmax_frequency_hz = 0.5\n')" --speed-kmh 100 --out "$WORK/o"
expect 2 "--speeds must be >= 1" -- "$VIADUCT" tradeoff "$(scen tspeeds '[sweep]\nspeeds_kmh = [100]\n')" --speeds 0 --out "$WORK/o"
expect 2 "no speeds" -- "$VIADUCT" tradeoff "$(scen tnospeeds '')" --out "$WORK/o"

# Identification (issue #4): records and FRF files that cannot be used, named.
HS=$SRC/scenarios/hslm-simply-supported.toml
"$VIADUCT" shaker "$HS" --force-at 5 --stepped 4.5:5.5:0.5 --dwell-s 12 --fs-hz 100 --quiet --out "$WORK/sh"
expect 2 "missing force channel" -- "$VIADUCT" frf "$WORK/sh/record.csv" --out "$WORK/o"
expect 2 "no channel 'thrust'" -- "$VIADUCT" frf "$WORK/sh/record.csv" --force thrust --out "$WORK/o"
expect 2 "must be in N or kN" -- "$VIADUCT" frf "$WORK/sh/record.csv" --force mid_acc --out "$WORK/o"
awk -F, 'BEGIN { OFS = "," } /^#/ || /^t_s/ { print; next } { $2 = 0; print }' "$WORK/sh/record.csv" > "$WORK/zero.csv"
expect 2 "the force channel is zero" -- "$VIADUCT" frf "$WORK/zero.csv" --force force_N --out "$WORK/o"
awk -F, 'BEGIN { OFS = "," } /^#/ { next } /^t_s/ { print; next } { $1 = $1 * 2; print }' "$WORK/sh/record.csv" > "$WORK/slow.csv"
expect 2 "mismatched sampling rates" -- "$VIADUCT" frf "$WORK/sh/record.csv" --force force_N --force-record "$WORK/slow.csv" --out "$WORK/o"
expect 0 "detected 3 steps from the force (4.5 to 5.5 Hz)" -- "$VIADUCT" frf "$WORK/sh/record.csv" --force force_N --method stepped --out "$WORK/o"
expect 2 "cycles left after settling" -- "$VIADUCT" frf "$WORK/sh/record.csv" --force force_N --method stepped --steps "$WORK/sh/steps.csv" --settle-cycles 50 --out "$WORK/o"
printf 't_start_s,t_end_s,frequency_hz\n0,12,4.5\n12,24,7.5\n' > "$WORK/wrong-steps.csv"
expect 2 "not a sine at the scheduled frequency" -- "$VIADUCT" frf "$WORK/sh/record.csv" --force force_N --method stepped --steps "$WORK/wrong-steps.csv" --out "$WORK/o"
expect 2 "--set applies to scenarios" -- "$VIADUCT" frf "$WORK/sh/record.csv" --force force_N --set bridge.EI=1 --out "$WORK/o"
expect 2 "--force-at X" -- "$VIADUCT" frf "$HS" --out "$WORK/o"
expect 2 "is not on the deck" -- "$VIADUCT" frf "$HS" --force-at 5 --response-at far=40 --out "$WORK/o"
expect 2 "give exactly one of" -- "$VIADUCT" shaker "$HS" --force-at 5 --out "$WORK/o"
expect 2 "Nyquist" -- "$VIADUCT" shaker "$HS" --force-at 5 --stepped 4:60:1 --fs-hz 100 --out "$WORK/o"
expect 2 "the first column must be frequency_hz, not 't_s'" -- "$VIADUCT" modal-fit "$WORK/sh/record.csv" --out "$WORK/o"
expect 0 "" -- "$VIADUCT" frf "$WORK/sh/record.csv" --force force_N --method stepped --steps "$WORK/sh/steps.csv" --out "$WORK/f" --quiet
expect 2 "fewer than 5 frequencies in the band" -- "$VIADUCT" modal-fit "$WORK/f/frf.csv" --out "$WORK/o"
expect 2 "--channel is required" -- "$VIADUCT" decay "$WORK/sh/record.csv" --frequency-hz 5 --out "$WORK/o"
expect 2 "too short a decay" -- "$VIADUCT" decay "$WORK/sh/record.csv" --channel mid_acc --frequency-hz 5 --start-s 35.5 --out "$WORK/o"
# A window left empty says why (was "0 cycles between 3.75 s and 3.13 s"); --end-s bounds it (#19).
SYN=$SRC/data/records/synthetic-deck.csv
expect 2 "the decay given at 5.5 s, after the 4 cycles skipped for the filter's transient (to 5.9 s), leaves nothing before 5.816 s" -- "$VIADUCT" decay "$SYN" --channel deck_acc --frequency-hz 10 --start-s 5.5 --out "$WORK/o"
expect 2 "sinks into the noise or the record ends after 14.16 cycles of 10 Hz (from 4.4 s: the decay given at 4 s plus 4 cycles skipped, to 5.816 s), at least 50 needed (--min-cycles)" -- "$VIADUCT" decay "$SYN" --channel deck_acc --frequency-hz 10 --start-s 4 --min-cycles 50 --out "$WORK/o"
expect 2 "--end-s" -- "$VIADUCT" decay "$SYN" --channel deck_acc --frequency-hz 10 --start-s 4 --end-s 3 --out "$WORK/o"
expect 0 "wrote" -- "$VIADUCT" decay "$SYN" --channel deck_acc --frequency-hz 10 --start-s 4 --end-s 5.4 --skip-cycles 2 --min-cycles 3 --out "$WORK/dend"
expect 2 "go together" -- "$VIADUCT" decay "$WORK/sh/record.csv" --channel mid_acc --frequency-hz 5 --speed-kmh 100 --out "$WORK/o"
# viaduct fit: every refusal names the option or key; a fit that cannot finish exits 1 with the reason.
FS=$(scen fitok '[run]\nspeed_kmh = 100\n')
"$VIADUCT" run "$FS" --quiet --out "$WORK/fr" >/dev/null 2>&1
expect 2 "no parameter to fit" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --out "$WORK/o"
expect 2 "key 'bridge.EJ': unknown scenario key" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.EJ=1e9:4e9 --out "$WORK/o"
expect 2 "key 'bridge.EI': bounds must be finite with lower < upper" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.EI=4e9:1e9 --out "$WORK/o"
expect 2 "key 'bridge.EI': its value 2000000000 (the start) is outside the bounds [3000000000, 4000000000]" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.EI=3e9:4e9 --out "$WORK/o"
expect 2 "key 'bridge.damping.ratio': bound 2 violates the key's constraint [0, 1)" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.damping.ratio=0:2 --out "$WORK/o"
expect 2 "cannot open" -- "$VIADUCT" fit "$FS" --record "$WORK/nothere.csv" --map mid_acc_mps2=mid --param bridge.EI=1e9:4e9 --out "$WORK/o"
expect 2 "no station 'nowhere'" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=nowhere --param bridge.EI=1e9:4e9 --out "$WORK/o"
expect 2 "deck_acc" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map deck_acc=mid --param bridge.EI=1e9:4e9 --out "$WORK/o"
expect 2 "channel 'force_N' is in N; only accelerations (_mps2, [g], ...), velocities (_mps, [mm/s], ...), deflections (_m, [mm], ...) and strains (_ue, [µε], ...) compare with the model" -- "$VIADUCT" fit "$FS" --record "$WORK/sh/record.csv" --map force_N=mid --param bridge.EI=1e9:4e9 --out "$WORK/o"
expect 2 "--weight: unknown objective 'phase'" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.EI=1e9:4e9 --weight phase=1 --out "$WORK/o"
expect 2 "one speed for all records or one per --record" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.EI=1e9:4e9 --speed-kmh 100 --speed-kmh 110 --out "$WORK/o"
expect 2 "nothing to fit against" -- "$VIADUCT" fit "$FS" --param bridge.EI=1e9:4e9 --out "$WORK/o"
expect 2 "the modal and damping objectives need --modes" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.EI=1e9:4e9 --weight modal=1 --out "$WORK/o"
expect 2 "fit: error: --starts = 0: violated constraint starts >= 1" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.EI=1e9:4e9 --starts 0 --out "$WORK/o"
expect 2 "given twice" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.EI=1e9:4e9 --param bridge.EI=1e9:5e9 --out "$WORK/o"
mkdir -p "$WORK/md"
printf 'method,mode,frequency_hz,damping_ratio,response,note\nlscf,1,4.0,0.02,all,\n' > "$WORK/md/modes.csv"
printf 'method,mode,response,re,im\nlscf,1,sensor7,1,0\n' > "$WORK/md/shapes.csv"
expect 2 "response 'sensor7' is not a station of the scenario: add --map sensor7=STATION" -- "$VIADUCT" fit "$FS" --modes "$WORK/md" --param bridge.EI=1e9:4e9 --out "$WORK/o"
expect 0 "converged" -- "$VIADUCT" fit "$FS" --modes "$WORK/md" --map sensor7=mid --param bridge.EI=1e9:4e9 --out "$WORK/o"
expect 2 "no mode of method 'circle-fit'" -- "$VIADUCT" fit "$FS" --modes "$WORK/md" --modes-method circle-fit --param bridge.EI=1e9:4e9 --out "$WORK/o"
expect 2 "fitbad.toml:10: key 'bridge.EJ': unknown scenario key" -- "$VIADUCT" fit "$(scen fitbad '[[fit.params]]\nkey = "bridge.EJ"\nlower = 1e9\nupper = 4e9\n')" --out "$WORK/o"
expect 2 "fitbad2.toml:10: key 'fit.starts': must be >= 1" -- "$VIADUCT" fit "$(scen fitbad2 '[fit]\nstarts = 0\n')" --out "$WORK/o"
expect 1 "did not converge" -- "$VIADUCT" fit "$FS" --record "$WORK/fr/history.csv" --map mid_acc_mps2=mid --param bridge.EI=1e9:4e9 --param bridge.damping.ratio=0:0.1 --set bridge.EI=1.2e9 --max-iterations 1 --out "$WORK/o"
[ -s "$WORK/o/fit.csv" ] && grep -q 'status = "no_convergence"' "$WORK/o/fit.toml" && n_pass=$((n_pass + 1)) || { echo "FAIL: a fit without convergence writes fit.csv and says so in fit.toml"; n_fail=$((n_fail + 1)); }
# A sweep factor that breaks its key's rule fails that variant's cases (exit 1, failures.csv
# says why); the reference and the other variants are computed. viaduct check refuses it (2).
FACT='[sweep]\nspeeds_kmh = [100, 150]\n[[sweep.variants]]\nkey = "bridge.EI"\nfactors = [0.0, 2.0]\n'
expect 1 "" -- "$VIADUCT" sweep "$(scen factor "$FACT")" --quiet --out "$WORK/factor"
expect 0 "bridge.EI x0,train,100,\"variant 'bridge.EI x0': $WORK/factor.toml:12: key 'sweep.variants[0].key': factor 0 breaks the rule of" -- cat "$WORK/factor/failures.csv"
expect 0 "bridge.EI x2,2,train,150,mid," -- cat "$WORK/factor/envelope.csv"
expect 2 "factor 0 breaks the rule of" -- "$VIADUCT" check "$(scen factor "$FACT")"
# One exit code per kind of error (#18): a value that makes every case's input wrong exits 2 from
# run and from sweep (which still lists the cases in failures.csv); partial failures exit 1 (above).
expect 2 "records 1e+303 samples" -- "$VIADUCT" run "$HS" --set analysis.free_vibration_s=1e300 --out "$WORK/o"
expect 2 "hslm-simply-supported.toml: every case failed on its input (failures.csv): a run of 1e+300 s" -- "$VIADUCT" sweep "$HS" --set analysis.free_vibration_s=1e300 --set 'train.files=["hslm:A1"]' --set sweep.speed_step_kmh=140 --quiet --out "$WORK/allbad"
expect 0 "HSLM-A1,420," -- cat "$WORK/allbad/failures.csv"
# Strain gauges (#20): the fibre's distance is checked at its key.
expect 2 "fibre0.toml:9: key 'stations[0].fibre_m': the fibre's distance from the neutral axis must be non-zero" -- "$VIADUCT" check "$(scen fibre0 'fibre_m = 0.0\n')"
expect 2 "fibre20.toml:9: key 'stations[0].fibre_m': the fibre's distance from the neutral axis must be non-zero and within 10 m of it (a deck is not deeper), got 20" -- "$VIADUCT" check "$(scen fibre20 'fibre_m = 20.0\n')"
# Grid variants (#22): one column per varied key, the factor of each row's variant on it; two
# entries on one key share its column.
GRID='[sweep]\nspeeds_kmh = [100]\nmode = "grid"\n[[sweep.variants]]\nkey = "bridge.EI"\nfactors = [1.0, 2.0]\n[[sweep.variants]]\nkey = "bridge.damping.ratio"\nfactors = [0.5, 1.0]\n'
expect 0 "" -- "$VIADUCT" sweep "$(scen grid "$GRID")" --quiet --out "$WORK/grid"
expect 0 "variant,bridge.EI_factor,bridge.damping.ratio_factor,train,speed_kmh,station," -- head -1 "$WORK/grid/envelope.csv"
expect 0 "\"bridge.EI x2, bridge.damping.ratio x0.5\",2,0.5,train,100,mid," -- cat "$WORK/grid/envelope.csv"
expect 0 "bridge.EI x2,2,1,train,100,mid," -- cat "$WORK/grid/envelope.csv"
TWICE='[sweep]\nspeeds_kmh = [100]\n[[sweep.variants]]\nkey = "bridge.EI"\nlabel = "low"\nfactors = [0.5]\n[[sweep.variants]]\nkey = "bridge.EI"\nlabel = "high"\nfactors = [2.0]\n'
expect 0 "" -- "$VIADUCT" sweep "$(scen twice "$TWICE")" --quiet --out "$WORK/twice"
expect 0 "variant,bridge.EI_factor,train" -- head -1 "$WORK/twice/envelope.csv"
expect 0 "high x2,2,train,100,mid," -- cat "$WORK/twice/envelope.csv"
# A sweep without variants keeps the plain columns.
expect 0 "" -- "$VIADUCT" sweep "$(scen plain '[sweep]\nspeeds_kmh = [100]\n')" --quiet --out "$WORK/plain"
expect 0 "variant,train,speed_kmh,station" -- head -1 "$WORK/plain/envelope.csv"
# A track of one rail line (half a deck) under whole axle loads warns (#22); its two-rail,
# full-deck version under whole loads does not.
expect 0 "warning: the track is one rail line on half a deck (track.rails = \"one\") and train.load_factor = 1" -- "$VIADUCT" check "$OG" --set train.load_factor=1.0
expect 0 "no warning" -- bash -c '"$@" 2>&1 | grep -q "warning:" && echo warned || echo "no warning"' _ "$VIADUCT" check "$OG" --set "bridge.file=\"$SRC/data/bridges/old-guadiana-full-deck.toml\"" --set "track.file=\"$SRC/data/tracks/old-guadiana-ballasted-two-rails.toml\"" --set train.load_factor=1.0
# First-week frictions (#22): a mistyped command, a station that is not there, help defaults.
expect 2 "unknown command 'swep' (did you mean 'sweep'?)" -- "$VIADUCT" swep "$OG"
expect 2 "--map: no station 'S9' in the scenario; it has: S1_mid S1_3L4 S2_mid" -- "$VIADUCT" compare "$SRC/scenarios/old-guadiana-talgo.toml" --record "$SRC/data/records/synthetic-deck.csv" --map deck_acc=S9 --out "$WORK/o"
expect 0 "--band-ratio arg (=0.15)" -- "$VIADUCT" decay --help
expect 0 "--cluster-tol arg (=0.005)" -- "$VIADUCT" modal-fit --help
# --unset: a speed list replaces the scenario's range from the command line (#22).
expect 2 "give speeds one way only: speeds_kmh, or speed_min/max/step_kmh, or speed_min/max_mps with n_speeds (on the command line, --unset the keys of the other way)" -- "$VIADUCT" sweep "$OG" --set 'sweep.speeds_kmh=[154.8]' --out "$WORK/o"
expect 0 "1 speeds x 1 trains x 1 variants" -- "$VIADUCT" check "$OG" --unset sweep.speed_min_mps --unset sweep.speed_max_mps --unset sweep.n_speeds --unset sweep.variants --set 'sweep.speeds_kmh=[154.8]'
expect 2 "--unset: key 'sweep.speed_mni_mps': unknown key (did you mean 'sweep.speed_min_mps'?)" -- "$VIADUCT" check "$OG" --unset sweep.speed_mni_mps
expect 2 "--unset: key 'sweep.speeds_kmh': is not set in the scenario" -- "$VIADUCT" check "$OG" --unset sweep.speeds_kmh
expect 2 "--set sweep.n_speeds and --unset sweep.n_speeds: give a key one of them" -- "$VIADUCT" check "$OG" --unset sweep.n_speeds --set sweep.n_speeds=3
expect 2 "--set and --unset change scenario keys; viaduct spectrum takes no scenario" -- "$VIADUCT" spectrum "$SRC/data/records/synthetic-deck.csv" --unset x
expect 2 "--set: key 'title': the value is not UTF-8 text or holds a control character" -- "$VIADUCT" check "$OG" --set $'title=\'a\xff\''
# viaduct assess: its keys break their rules with file, line and key; what it needs is named.
AS='[assess]\nline_speed_kmh = 200.0\ndeck_type = "prestressed"\n'
expect 2 "aneg.toml:12: key 'assess.acceleration_limit_mps2': must be > 0 [m/s²], got -3.5" -- "$VIADUCT" assess "$(scen aneg "${AS}acceleration_limit_mps2 = -3.5\n")" --no-plots --out "$WORK/o"
expect 2 "v0.toml:10: key 'assess.line_speed_kmh': must be > 0 [km/h], got 0" -- "$VIADUCT" assess "$(scen v0 '[assess]\nline_speed_kmh = 0.0\ndeck_type = "steel"\n')" --no-plots --out "$WORK/o"
expect 2 "timber.toml:11: key 'assess.deck_type': must be one of steel|composite|prestressed|reinforced|filler-beam" -- "$VIADUCT" assess "$(scen timber '[assess]\nline_speed_kmh = 200.0\ndeck_type = "timber"\n')" --no-plots --out "$WORK/o"
expect 2 "nodeck.toml:10: key 'assess.deck_type': viaduct assess needs this key" -- "$VIADUCT" assess "$(scen nodeck '[assess]\nline_speed_kmh = 200.0\n')" --no-plots --out "$WORK/o"
expect 2 "--set: key 'assess.deflection_limit_ratio': must be > 0, got -600" -- "$VIADUCT" assess "$(scen dneg "$AS")" --set assess.deflection_limit_ratio=-600 --no-plots --out "$WORK/o"
expect 2 "comfort.toml:12: key 'assess.comfort_level': must be one of very-good|good|acceptable, got 'excellent'" -- "$VIADUCT" assess "$(scen comfort "${AS}comfort_level = \"excellent\"\n")" --no-plots --out "$WORK/o"
expect 2 "--set: key 'train.comfort_lowpass_hz': Cheby1Spec::high_hz = 600: violated constraint high_hz in (0, fs/2 = 500) Hz" -- "$VIADUCT" run "$SRC/scenarios/vehicles-25m.toml" --set train.comfort_lowpass_hz=600 --out "$WORK/o"
expect 2 "--set: key 'assess.unloading_ratio_limit': must be (0, 1], got 1.2" -- "$VIADUCT" assess "$(scen unl "$AS")" --set assess.unloading_ratio_limit=1.2 --no-plots --out "$WORK/o"
expect 2 "asks for HSLM-B; give assess.hslm_b_n and assess.hslm_b_spacing_m" -- "$VIADUCT" assess "$(scen short "$AS")" --set "bridge.span_lengths=[5.0]" --no-plots --out "$WORK/o"
expect 2 "lneg.toml:12: key 'assess.determinant_length_m': must be > 0 [m], got -24" -- "$VIADUCT" assess "$(scen lneg "${AS}determinant_length_m = -24.0\n")" --no-plots --out "$WORK/o"
expect 2 "--set: key 'bridge.continuous': must be a boolean, got 3" -- "$VIADUCT" check "$OG" --set bridge.continuous=3
expect 2 "key 'assess.ballast_lower_factor': the lower-bound factor is above the upper-bound one" -- "$VIADUCT" assess "$(scen lohi "${AS}ballast_lower_factor = 1.5\n")" --no-plots --out "$WORK/o"
# Every case failing on its input: exit 2, as run and sweep; the report says no check was made.
expect 2 "every case failed on its input" -- "$VIADUCT" assess "$(scen allbad "$AS")" --set analysis.free_vibration_s=1e300 --no-plots --out "$WORK/allbad"
expect 0 "No check could be made" -- cat "$WORK/allbad/report.md"
# viaduct passages: tables and trains checked before any run, every problem named.
PT=$SRC/data/records/passages/passages.csv
expect 2 "--records FOLDER|TABLE is required" -- "$VIADUCT" passages "$HS" --map mid_acc=mid --out "$WORK/o"
expect 2 "--records $WORK/nothere: no such folder or table" -- "$VIADUCT" passages "$HS" --records "$WORK/nothere" --map mid_acc=mid --out "$WORK/o"
expect 2 "at least one --map CHANNEL=STATION is required" -- "$VIADUCT" passages "$HS" --records "$PT" --out "$WORK/o"
expect 2 "--map: no station 'S9' in the scenario; it has: mid" -- "$VIADUCT" passages "$HS" --records "$PT" --map mid_acc=S9 --out "$WORK/o"
printf 'record_file,train\na.csv,HSLM-A1\n' > "$WORK/pt1.csv"
expect 2 "pt1.csv:1: key 'file': a table of passages needs a column 'file'" -- "$VIADUCT" passages "$HS" --records "$WORK/pt1.csv" --map mid_acc=mid --out "$WORK/o"
printf '# campaign 2026\nfile,train,speed_kmh\na.csv,HSLM-A1,fast\n' > "$WORK/pt2.csv"
expect 2 "pt2.csv:3: key 'speed_kmh': 'fast' is not a speed > 0 [km/h]" -- "$VIADUCT" passages "$HS" --records "$WORK/pt2.csv" --map mid_acc=mid --out "$WORK/o"
printf 'file,train\na.csv,ICE-9\nb.csv,HSLM-A1\nc.csv,\n' > "$WORK/pt3.csv"
expect 2 "pt3.csv:2: train 'ICE-9' is neither a train of the scenario" -- "$VIADUCT" passages "$HS" --records "$WORK/pt3.csv" --map mid_acc=mid --out "$WORK/o"
expect 2 "pt3.csv:4: no train for $WORK/c.csv: give a train column, --train, or a scenario with one train" -- "$VIADUCT" passages "$HS" --records "$WORK/pt3.csv" --map mid_acc=mid --out "$WORK/o"
printf 'file\n' > "$WORK/pt4.csv"
expect 2 "no passages in the table" -- "$VIADUCT" passages "$HS" --records "$WORK/pt4.csv" --map mid_acc=mid --out "$WORK/o"
# Every record unreadable: exit 2, each named.
printf 'file,train\nnothere1.csv,HSLM-A1\nnothere2.csv,HSLM-A1\n' > "$WORK/pt5.csv"
expect 2 "nothere2.csv: cannot open" -- "$VIADUCT" passages "$HS" --records "$WORK/pt5.csv" --map mid_acc=mid --set sweep.speed_step_kmh=140 --out "$WORK/o"
expect 2 "a strain; station 'mid' has no stations[].fibre_m" -- "$VIADUCT" passages "$HS" --records "$PT" --map mid_strain=mid --set sweep.speed_step_kmh=140 --out "$WORK/o"
expect 2 "key 'sweep': no speeds for the model's envelope" -- "$VIADUCT" passages "$HS" --records "$PT" --map mid_acc=mid --unset sweep --out "$WORK/o"
expect 2 "passages: --noise-band = 0: violated constraint noise_band > 0" -- "$VIADUCT" passages "$HS" --records "$PT" --map mid_acc=mid --noise-band 0 --set sweep.speed_step_kmh=140 --out "$WORK/o"
# viaduct irregularity: names and constraints.
expect 2 "unknown irregularity spectrum 'fra7' (known: fra1 ... fra6" -- "$VIADUCT" irregularity --spectrum fra7 --out "$WORK/o"
expect 2 "--spectrum is required" -- "$VIADUCT" irregularity --out "$WORK/o"
expect 2 "--lambda-min = 1: violated constraint lambda_min >= 4 dx" -- "$VIADUCT" irregularity --spectrum fra6 --dx 1 --out "$WORK/o"
expect 2 "--lambda-max = 80: violated constraint lambda_max <= length" -- "$VIADUCT" irregularity --spectrum fra6 --length 50 --out "$WORK/o"
expect 2 "takes no scenario" -- "$VIADUCT" irregularity --spectrum fra6 --set a=1 --out "$WORK/o"
# Vehicles: impossible parameters and combinations, with file, line and key.
VS=$SRC/scenarios/vehicles-25m.toml
expect 2 "key 'train.vehicle': multibody needs trains of coaches" -- "$VIADUCT" run "$VS" --set 'train.files=["hslm:A1"]' --out "$WORK/o"
expect 2 "key 'irregularity.spectrum': moving forces do not see the rail's profile" -- "$VIADUCT" run "$VS" --set train.vehicle=forces --out "$WORK/o"
# The vehicle fast path keeps its modes as the moving-load path does (one message).
expect 2 "keeps no mode: the lowest is" -- "$VIADUCT" run "$VS" --set 'analysis.method="modal"' --set modal.max_frequency_hz=0.5 --out "$WORK/o"
expect 2 "key 'irregularity.spectrum': must be one of" -- "$VIADUCT" check "$VS" --set irregularity.spectrum=fra9
sed 's/^body_mass_kg = .*/body_mass_kg = -47800.0/' "$SRC/data/vehicles/ave-s103.toml" > "$WORK/negcoach.toml"
printf 'kind = "coaches"\nvehicle = "negcoach.toml"\nn_coaches = 2\n' > "$WORK/negtrain.toml"
expect 2 "negcoach.toml:9: key 'body_mass_kg': -47800: violated constraint > 0 [kg]" -- "$VIADUCT" check "$VS" --set "train.files=[\"$WORK/negtrain.toml\"]"
sed 's/^wheelbase_m = .*/wheelbase_m = 18.0/' "$SRC/data/vehicles/ave-s103.toml" > "$WORK/wbcoach.toml"
printf 'kind = "coaches"\nvehicle = "wbcoach.toml"\nn_coaches = 2\n' > "$WORK/wbtrain.toml"
expect 2 "key 'bogie_spacing_m': 17.375: violated constraint > wheelbase (the bogies would overlap)" -- "$VIADUCT" check "$VS" --set "train.files=[\"$WORK/wbtrain.toml\"]"
printf 'x_m,z_mm\n0,0\n1,0.5\n2,0\n3,-0.5\n4,0\n' > "$WORK/shortprofile.csv"
expect 2 "irregularity.profile covers x = 0 to 4 m; the run needs -100 to 45 m" -- "$VIADUCT" run "$VS" --set irregularity.spectrum= --set "irregularity.profile=$WORK/shortprofile.csv" --out "$WORK/o"
expect 2 "key 'train.contact': rigid under a wheel with mass on the modal fast path takes no static correction" -- "$VIADUCT" run "$VS" --set train.contact=rigid --set analysis.method=modal --set modal.max_frequency_hz=60 --out "$WORK/o"
expect 2 "train.end_transition_m = 30 m reaches the bridge" -- "$VIADUCT" run "$OG" --set "train.files=[\"$SRC/data/trains/ave-s103-8.toml\"]" --set train.vehicle=multibody --set train.end_transition_m=30 --speed-kmh 200 --out "$WORK/o"
expect 2 "key 'analysis.superposition': unit-response composes constant axle loads" -- "$VIADUCT" sweep "$VS" --set analysis.superposition=unit-response --out "$WORK/o"
expect 2 "key 'train.contact': rigid under a wheel with mass is an index-3 constraint IDA does not take" -- "$VIADUCT" run "$VS" --set analysis.method=ida --set modal.max_frequency_hz=60 --set train.contact=rigid --out "$WORK/o"
expect 2 "key 'analysis.method': ida with vehicles integrates the structure's modes: give modal.max_frequency_hz" -- "$VIADUCT" run "$VS" --set analysis.method=ida --out "$WORK/o"
finish
