#!/usr/bin/env bash
# Runs the README's commands and the studies of scripts/measure/bench.sh (speed lists shortened where a
# full list would take minutes; every kernel and code path of the full runs is exercised) with one
# viaduct binary and writes every output under DIR, so that a refactor can be checked to change
# no result: run it with the binary before and after, then scripts/measure/compare_outputs.py A B.
#
#   scripts/measure/snapshot_outputs.sh DIR [VIADUCT]      (VIADUCT: default build/release/viaduct)
#
# Takes about 3 minutes on 2 cores. Wall times and versions are left for compare_outputs.py to
# ignore.
set -euo pipefail
cd "$(dirname "$0")/../.."
[ $# -ge 1 ] || { sed -n '2,9p' "$0"; exit 2; }
D=$1
V=$(realpath "${2:-build/release/viaduct}")
rm -rf "$D"
mkdir -p "$D"
run() {  # name command args... (outputs in $D/name)
  local name=$1
  shift
  "$V" "$@" --quiet --out "$D/$name" > "$D/$name.stdout" 2> "$D/$name.stderr" || echo "exit $?" >> "$D/$name.stdout"
}
OG=scenarios/old-guadiana-sensitivity.toml
TA=scenarios/old-guadiana-talgo.toml
HS=scenarios/hslm-simply-supported.toml
REC=data/records/synthetic-deck.csv
HSLM3='train.files=["data/trains/hslm/A1.toml","data/trains/hslm/A5.toml","data/trains/hslm/A9.toml"]'

# README: demo and "Using viaduct"
run demo-modes modes $OG --n-modes 10
run demo-sweep sweep $OG --threads 2 --set sweep.n_speeds=8
run modes modes $OG
run talgo run $TA
run hslm sweep $HS --threads 2 --set "$HSLM3"
run hslm-fast sweep $HS --threads 2 --set 'analysis.preset="fast"'
run og-modal sweep $OG --threads 2 --set 'analysis.preset="default"'
run og-fast sweep $OG --threads 2 --set 'analysis.preset="fast"' --set sweep.n_speeds=12
run hslm-unit sweep $HS --threads 2 --set 'analysis.superposition="unit-response"' --set "$HSLM3"
run hslm-3modes sweep $HS --set 'analysis.method="modal"' --set modal.n_modes=3 --set filter.enabled=false \
  --set analysis.dt=0.0005 --threads 2
run tradeoff tradeoff $OG --speeds 4 --threads 2
# records
run filter filter $REC --low-hz 1 --high-hz 30
run spectrum spectrum $REC
run psd spectrum "$D/talgo/history.csv" --welch --nperseg 2048
run peaks peaks $REC --channel deck_acc --max-peaks 3
run peaks-time peaks $REC --channel deck_disp --time --min-distance 0.2 --max-peaks 0
run lowpass filter $REC --band lowpass --high-hz 15 --channel deck_acc
run psd-rec spectrum $REC --welch --nperseg 1024 --detrend linear
run decimate resample $REC --decimate 5
run upsample resample $REC --fs-hz 4096 --channel deck_acc
run rms envelope $REC --kind rms --window-s 0.5
run hilbert envelope $REC --kind hilbert --channel deck_acc
run speed-peaks speed $REC --channel deck_disp --distance-m 13.14 --peaks --min-interval-s 0.2
run speed speed $REC --channel deck_acc --distance-m 13.14 --v-min-kmh 100 --v-max-kmh 250
run compare compare $TA --record $REC --map deck_acc=S1_mid --map deck_disp_m=S1_mid
run compare-v compare $TA --record $REC --map deck_acc=S1_mid --map deck_disp_m=S1_mid --speed-kmh 155.2
# forced vibration walk-through (shorter schedule)
run shaker shaker $TA --force-at 6 --stepped 9.5:10.5:0.1 --dwell-s 4 --fs-hz 100 --snr-db 40
run frf frf "$D/shaker/record.csv" --force force_N --method stepped --steps "$D/shaker/steps.csv" --settle-cycles 20
run frf-detected frf "$D/shaker/record.csv" --force force_N --method stepped --settle-cycles 15
run frf-welch frf "$D/shaker/record.csv" --force force_N --method welch --nperseg 256 --f-min 5 --f-max 15
run modal-fit-test modal-fit "$D/frf/frf.csv" --max-order 8 --model $TA
run shaker-swept shaker $HS --force-at 7 --swept 2:30 --sweep-s 20 --snr-db 40 --fs-hz 100
run frf-swept frf "$D/shaker-swept/record.csv" --force force_N --method swept --f-min 3 --f-max 28
run modal-fit-swept modal-fit "$D/frf-swept/frf.csv" --f-min 3 --f-max 28 --max-order 16 --no-refine
run frf-model frf $TA --force-at 6 --f-min 8 --f-max 12 --n-freq 401
run modal-fit modal-fit "$D/frf-model/frf.csv" --max-order 12 --model $TA
run passage run $TA --set analysis.free_vibration_s=5
run decay decay "$D/passage/history.csv" --channel S1_mid_acc --frequency-hz 10
run decay-start decay "$D/passage/history.csv" --channel S1_mid_acc --frequency-hz 10 --start-s 1.5 --window-cycles 3
run decay-train decay "$D/passage/history.csv" --channel S1_mid_acc --frequency-hz 10 --entry-s 0.465 \
  --speed-kmh 154.8 --train-length-m 109.02 --bridge-length-m 23.86
# model updating (one parameter pair, a few iterations)
run fit fit $TA --record data/records/og-calibration.csv --map S1_mid_acc=S1_mid --map S2_mid_acc=S2_mid \
  --param bridge.EI=5e9:1e10 --param bridge.damping.ratio1=0.01:0.06 --threads 2
# scripts/measure/bench.sh studies (speed lists shortened)
for dt in 0.002 0.0005; do
  run "bench-dt-$dt" sweep $OG --set analysis.dt=$dt --set sweep.mode=reference --threads 2 --set sweep.n_speeds=6
done
for kind in modal rayleigh; do
  run "bench-damp-hslm-$kind" sweep $HS --threads 1 --set bridge.damping.kind=$kind --set bridge.damping.f1_hz=5 \
    --set bridge.damping.ratio1=0.0135 --set bridge.damping.f2_hz=45 --set bridge.damping.ratio2=0.0135 \
    --set 'train.files=["data/trains/hslm/A1.toml"]' --set sweep.speed_step_kmh=7
done
run bench-og-m180 sweep $OG --threads 2 --set 'analysis.preset="fast"' --set modal.max_frequency_hz=180 \
  --set modal.damping_vectors=1 --set sweep.n_speeds=6
run bench-og-m90-dv0 sweep $OG --threads 2 --set 'analysis.preset="fast"' --set modal.damping_vectors=0 \
  --set sweep.n_speeds=6
for m in newmark modal; do
  run "bench-run-$m" run $OG --set run.speed_kmh=288 --set track.approach_length=10 --set track.exit_length=10 \
    --set "analysis.method=\"$m\"" --set modal.max_frequency_hz=180
done
HSLM10='train.files=["data/trains/hslm/A1.toml","data/trains/hslm/A2.toml","data/trains/hslm/A3.toml","data/trains/hslm/A4.toml","data/trains/hslm/A5.toml","data/trains/hslm/A6.toml","data/trains/hslm/A7.toml","data/trains/hslm/A8.toml","data/trains/hslm/A9.toml","data/trains/hslm/A10.toml"]'
for cfg in "newmark direct" "newmark unit-response" "modal unit-response" "modal direct"; do
  read -r m sp <<<"$cfg"
  run "bench-unit-$m-$sp" sweep $OG --set "$HSLM10" --set train.load_factor=0.5 --set sweep.mode=reference \
    --set sweep.n_speeds=3 --set "analysis.method=\"$m\"" --set "analysis.superposition=\"$sp\"" \
    --set modal.max_frequency_hz=180 --threads 2
done
run bench-ida-sweep sweep $HS --set 'analysis.method="ida"' --set 'train.files=["data/trains/hslm/A1.toml"]' \
  --set sweep.speed_step_kmh=70 --threads 2
# Vehicles through every coupled kernel, and the shaker's three quantities (issue #37 item 1).
VS=scenarios/vehicles-25m.toml
run veh-newmark run $VS
run veh-modal run $VS --set 'analysis.method="modal"'
run veh-modal-nosc run $VS --set 'analysis.method="modal"' --set modal.static_correction=false
run veh-ida run $VS --set 'analysis.method="ida"' --set modal.max_frequency_hz=60
run veh-rigid run $VS --set 'train.contact="rigid"'
# The fast path on a discrete track: the dashpots couple the modes (kept coupled, no complex basis).
run veh-track-modal run $TA --set 'train.files=["data/trains/ave-s103-8.toml"]' --set 'train.vehicle="sprung"' \
  --set 'analysis.method="modal"' --set run.speed_kmh=250
run veh-sprung-sweep sweep $VS --set 'train.vehicle="sprung"' --set 'analysis.method="modal"' --set sweep.speed_step_kmh=60 --threads 2
run veh-sweep-effects sweep $VS --set 'analysis.method="modal"' --set sweep.speed_step_kmh=120 --load-effects --threads 2
run shaker-vel shaker $TA --force-at 6 --stepped 9.5:10.5:0.5 --dwell-s 2 --fs-hz 100 --quantity vel
run shaker-disp shaker $HS --force-at 7 --swept 2:30 --sweep-s 5 --fs-hz 100 --quantity disp
echo "snapshot written to $D" >&2
