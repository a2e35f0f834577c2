# Every plot script renders from a small run of the command it draws (#22): it exits 0, says
# what it wrote, and the PNG is there and not a blank page. Uses Debian's python3 with
# matplotlib (scripts/setup.sh installs it).
. "$(dirname "$0")/lib.sh"
PY=/usr/bin/python3
P=$SRC/scripts/plot
HS=$SRC/scenarios/hslm-simply-supported.toml
OG=$SRC/scenarios/old-guadiana-talgo.toml
REC=$SRC/data/records/synthetic-deck.csv

# plotted NAME PNG -- command...: the plot command succeeds and PNG is a real image (> 15 kB: an
# empty 110 dpi figure with a title is about 10 kB).
plotted() {
  local png=$2
  shift 3
  rm -f "$png"
  expect 0 "wrote $png" -- "$@"
  local size
  size=$(stat -c %s "$png" 2>/dev/null || echo 0)
  if [ "$size" -gt 15000 ] && head -c 8 "$png" | grep -q PNG; then
    n_pass=$((n_pass + 1))
  else
    echo "FAIL: $png is missing or too small ($size bytes)"
    n_fail=$((n_fail + 1))
  fi
}

# Sampled studies (#16): percentile bands and exceedance, Sobol indices (2 base points and 4 speeds:
# cheap, and every panel drawn).
"$VIADUCT" sweep "$SRC/scenarios/old-guadiana-sampled.toml" --set sweep.n_samples=2 --set sweep.n_speeds=4 \
  --set sweep.sensitivity=true --quiet --out "$WORK/sampled"
plotted sampled "$WORK/sampled/sampled.png" -- $PY "$P/plot_sampled.py" "$WORK/sampled"
plotted sampled "$WORK/sampled/sensitivity.png" -- $PY "$P/plot_sampled.py" "$WORK/sampled"
"$VIADUCT" sweep "$HS" --set 'train.files=["hslm:A1-A3"]' --set sweep.speed_step_kmh=20 --quiet --out "$WORK/trains"
plotted envelope "$WORK/trains/envelope.png" -- $PY "$P/plot_envelope.py" "$WORK/trains"
plotted envelope "$WORK/trains/envelope_disp.png" -- $PY "$P/plot_envelope.py" "$WORK/trains" --quantity disp
# Moment and shear along the span (stations every 0.5 m: 31 of them), from a sweep and from an
# assessment (with the dynamic design effect and Phi x LM71 x alpha along x).
ALONG=(--set 'stations[1].name="L"' --set stations[1].span=1)
"$VIADUCT" sweep "$HS" --set 'train.files=["hslm:A1-A3"]' --set sweep.speed_step_kmh=20 "${ALONG[@]}" \
  --set stations[1].every_m=0.5 --load-effects --quiet --out "$WORK/along"
plotted load_effects "$WORK/along/load_effects_along.png" -- $PY "$P/plot_load_effects.py" "$WORK/along"
# assess draws it itself (plot_assess.py) and the report shows it; the script redraws it alone.
"$VIADUCT" assess "$HS" --no-pdf --set assess.speed_min_kmh=300 --set assess.speed_step_kmh=20 --set assess.refine_band=0 \
  "${ALONG[@]}" --set stations[1].every_m=1.5 --quiet --out "$WORK/along-assess"
expect 0 "](load_effects_along.png)" -- cat "$WORK/along-assess/report.md"
expect 0 "" -- test -s "$WORK/along-assess/load_effects_along.png"
plotted load_effects "$WORK/along-assess/load_effects_along.png" -- $PY "$P/plot_load_effects.py" "$WORK/along-assess"
expect 1 "load_effects.csv not found" -- $PY "$P/plot_load_effects.py" "$WORK/trains"
# Variants one at a time and a grid: one panel per varied key.
for m in one-at-a-time grid; do
  printf 'title = "Variants, %s"\n[bridge]\nspan_lengths = [15.0]\nEI = 7.694e9\nmass_per_m = 15000.0\n[bridge.damping]\nratio = 0.0135\n[train]\nfiles = ["hslm:A1-A2"]\n[[stations]]\nname = "mid"\nspan = 1\nat = 0.5\n[sweep]\nspeed_min_kmh = 150\nspeed_max_kmh = 400\nspeed_step_kmh = 25\nmode = "%s"\n[[sweep.variants]]\nkey = "bridge.EI"\nlabel = "EI"\nfactors = [0.9, 1.1]\n[[sweep.variants]]\nkey = "bridge.damping.ratio"\nfactors = [0.5, 2.0]\n' "$m" "$m" > "$WORK/$m.toml"
  "$VIADUCT" sweep "$WORK/$m.toml" --quiet --out "$WORK/$m"
  plotted envelope "$WORK/$m/envelope.png" -- $PY "$P/plot_envelope.py" "$WORK/$m"
done
# A grid is drawn whole or says how it is reduced: 2 x 2 combinations and the reference, each
# curve the maximum over the settings of the other key.
expect 0 "grid of 5 variants: each curve the maximum over every setting of the other keys" -- $PY "$P/plot_envelope.py" "$WORK/grid"

"$VIADUCT" run "$OG" --set analysis.free_vibration_s=4 --quiet --out "$WORK/run"
plotted history "$WORK/run/history.png" -- $PY "$P/plot_history.py" "$WORK/run"
# Vehicles: two coaches over the 25 m span, contact forces and car bodies.
printf 'kind = "coaches"\nvehicle = "%s"\nn_coaches = 2\n' "$SRC/data/vehicles/ave-s103.toml" > "$WORK/ave2.toml"
"$VIADUCT" run "$SRC/scenarios/vehicles-25m.toml" --set "train.files=[\"$WORK/ave2.toml\"]" --quiet --out "$WORK/vehicles"
plotted vehicles "$WORK/vehicles/vehicles.png" -- $PY "$P/plot_vehicles.py" "$WORK/vehicles"
expect 1 "vehicles.csv not found" -- $PY "$P/plot_vehicles.py" "$WORK/run"
"$VIADUCT" compare "$OG" --record "$REC" --map deck_acc=S1_mid --map deck_disp=S1_mid --quiet --out "$WORK/compare"
plotted compare "$WORK/compare/compare.png" -- $PY "$P/plot_compare.py" "$WORK/compare"
"$VIADUCT" decay "$WORK/run/history.csv" --channel S1_mid_acc --frequency-hz 10 --quiet --out "$WORK/decay"
plotted decay "$WORK/decay/decay.png" -- $PY "$P/plot_decay.py" "$WORK/decay"
"$VIADUCT" fatigue "$SRC/data/records/passages/passage-01.csv" --channel mid_strain --detail 71 --hysteresis-mpa 1 --quiet --out "$WORK/fatigue"
plotted fatigue "$WORK/fatigue/fatigue.png" -- $PY "$P/plot_fatigue.py" "$WORK/fatigue"
expect 1 "cycles.csv not found" -- $PY "$P/plot_fatigue.py" "$WORK/run"
"$VIADUCT" spectrum "$REC" --quiet --out "$WORK/spectrum"
"$VIADUCT" peaks "$REC" --max-peaks 3 --quiet --out "$WORK/spectrum"
plotted spectrum "$WORK/spectrum/spectrum.png" -- $PY "$P/plot_spectrum.py" "$WORK/spectrum" --f-max 20
"$VIADUCT" frf "$OG" --force-at 6 --f-min 5 --f-max 15 --n-freq 201 --quiet --out "$WORK/frf"
plotted frf "$WORK/frf/frf.png" -- $PY "$P/plot_frf.py" "$WORK/frf/frf.csv"
"$VIADUCT" modal-fit "$WORK/frf/frf.csv" --max-order 20 --quiet --out "$WORK/modal"
plotted stabilization "$WORK/modal/stabilization.png" -- $PY "$P/plot_stabilization.py" "$WORK/modal"
"$VIADUCT" tradeoff "$HS" --speeds 3 --set 'train.files=["hslm:A1"]' --quiet --out "$WORK/tradeoff"
plotted tradeoff "$WORK/tradeoff/tradeoff.png" -- $PY "$P/plot_tradeoff.py" "$WORK/tradeoff"
"$VIADUCT" run "$HS" --train HSLM-A4 --speed-kmh 300 --set 'train.files=["hslm:A4"]' --quiet --out "$WORK/a4"
"$VIADUCT" fit "$HS" --record "$WORK/a4/history.csv" --map mid_acc_mps2=mid --train HSLM-A4 --speed-kmh 300 \
  --set 'train.files=["hslm:A4"]' --param bridge.EI=5e9:1e10 --set bridge.EI=7e9 --quiet --out "$WORK/fit" || true
plotted fit "$WORK/fit/fit_trace.png" -- $PY "$P/plot_fit.py" "$WORK/fit"
plotted fit "$WORK/fit/fit_time.png" -- $PY "$P/plot_fit.py" "$WORK/fit"
"$VIADUCT" assess "$HS" --no-pdf --set assess.speed_min_kmh=300 --set assess.speed_step_kmh=20 --set assess.refine_band=0 --no-plots \
  --quiet --out "$WORK/assess"
for f in acc_vs_speed envelope phi_dyn; do
  plotted assess "$WORK/assess/$f.png" -- $PY "$P/plot_assess.py" "$WORK/assess"
done
# viaduct assess draws them itself and links them from report.md.
expect 0 "(with figures)" -- "$VIADUCT" assess "$HS" --no-pdf --set assess.speed_min_kmh=300 --set assess.speed_step_kmh=20 \
  --set assess.refine_band=0 --out "$WORK/assess2"
expect 0 "![Peak deck acceleration against speed" -- cat "$WORK/assess2/report.md"
"$VIADUCT" passages "$HS" --records "$SRC/data/records/passages/passages.csv" --map mid_acc=mid --map mid_disp=mid --set analysis.method=modal --set sweep.speed_step_kmh=20 --quiet --out "$WORK/passages"
plotted passages "$WORK/passages/passages.png" -- $PY "$P/plot_passages.py" "$WORK/passages"
finish
