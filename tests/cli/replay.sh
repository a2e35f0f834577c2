#!/usr/bin/env bash
# A manifest runs again (#37): for each command, `viaduct replay OUT/manifest.toml` writes every
# file of OUT byte for byte (the manifest itself and figures aside), from another directory.
. "$(dirname "$0")/lib.sh"
HS=$SRC/scenarios/hslm-simply-supported.toml
OG=$SRC/scenarios/old-guadiana-sensitivity.toml
TA=$SRC/scenarios/old-guadiana-talgo.toml
VS=$SRC/scenarios/vehicles-25m.toml
REC=$SRC/data/records/synthetic-deck.csv
mkdir -p "$WORK/a" "$WORK/b"

# round_trip NAME COMMAND ARGS...: the command into a/NAME, its replay (from b/) into b/NAME.
round_trip() {
  local name=$1
  shift
  expect 0 "" -- "$VIADUCT" "$@" --out "$WORK/a/$name" --quiet
  (cd "$WORK/b" && "$VIADUCT" replay "$WORK/a/$name/manifest.toml" --out "$WORK/b/$name" --quiet) > "$WORK/replay.log" 2>&1
  expect 0 "" -- cat "$WORK/replay.log"
  local f
  for f in "$WORK/a/$name"/*; do
    case "$f" in
      *manifest.toml|*.png) continue ;;
      *.pdf) continue ;;  # report.html printed: its creation date differs; the page itself is compared
      *report.md)  # its provenance line names the scenario and the command line as run: the manifest's
        expect 0 "" -- cmp <(grep -v '^Scenario `' "$f") <(grep -v '^Scenario `' "$WORK/b/$name/report.md") ;;
      *report.html)  # the same provenance paragraph
        expect 0 "" -- cmp <(grep -v '^<p>Scenario <code>' "$f") <(grep -v '^<p>Scenario <code>' "$WORK/b/$name/report.html") ;;
      *) expect 0 "" -- cmp "$f" "$WORK/b/$name/$(basename "$f")" ;;
    esac
  done
}

round_trip run run "$HS" --speed-kmh 250 --train HSLM-A4 --set bridge.damping.ratio=0.02
round_trip sweep sweep "$HS" --set 'train.files=["hslm:A1","hslm:A7"]' --set sweep.speed_step_kmh=20 --load-effects --threads 2
round_trip variants sweep "$OG" --set sweep.n_speeds=4 --threads 2
round_trip preset sweep "$OG" --set 'analysis.preset="default"' --set sweep.n_speeds=3
round_trip hht run "$HS" --set analysis.alpha=-0.1
round_trip vehicles run "$VS" --speed-kmh 200
round_trip modes modes "$TA"
round_trip compare compare "$TA" --record "$REC" --map deck_acc=S1_mid --map deck_disp=S1_mid
round_trip filter filter "$REC" --low-hz 1 --high-hz 30
round_trip passage run "$TA" --set analysis.free_vibration_s=5
round_trip decay decay "$WORK/a/passage/history.csv" --channel S1_mid_acc_mps2 --frequency-hz 10 --start-s 1.5
round_trip assess assess "$HS" --set assess.speed_step_kmh=20 --set assess.refine_step_kmh=10 --no-plots --no-pdf
# A replay refuses what it cannot reproduce: an input that changed, a file that is no manifest.
cp "$REC" "$WORK/rec.csv"
expect 0 "" -- "$VIADUCT" filter "$WORK/rec.csv" --out "$WORK/a/changed" --quiet
echo "6.018,0,0" >> "$WORK/rec.csv"
expect 2 "rec.csv changed since the run (its SHA-256 differs)" -- "$VIADUCT" replay "$WORK/a/changed/manifest.toml" --out "$WORK/b/changed"
expect 2 "not a viaduct manifest" -- "$VIADUCT" replay "$HS" --out "$WORK/b/x"
finish
