#!/usr/bin/env bash
# Sampled studies (#16) on the Old Guadiana model: shards (N = 1, 2, 7) and their merge, a run
# killed and resumed, and (argument 4 "mpi") 2 MPI ranks all give the files of one process byte
# for byte; bad distributions, shards and resumes are errors naming what is wrong.
# Argument 3: "full" (optimised build) or "light" (the sanitizers: fewer shards and samples, the
# same code paths).
. "$(dirname "$0")/lib.sh"
SIZE=${3:-full}
MPI=${4:-}
OG=$SRC/scenarios/old-guadiana-sampled.toml
FILES="samples.csv sample_peaks.csv failures.csv percentiles.csv peak_percentiles.csv"

# The study at a glance (lognormal mean 1, sd 0.3: its 1 % quantile exp(-0.04309 - 2.32635 x 0.29356)).
expect 0 "# sampled study: 64 samples (sobol design) x 60 speeds x 1 trains = 3840 cases" -- "$VIADUCT" check "$OG"
expect 0 "#   Kp (track.pad.k): lognormal factor, 1-99 % in [0.4838, 1.896]" -- "$VIADUCT" check "$OG"

# The study: Old Guadiana optimised; under the sanitizers a 15 m span without track, whose
# samples cost a hundredth (the same sampling, streaming, merging and statistics code).
if [ "$SIZE" = full ]; then
  SC=$OG; NA=7; SHARDS="1 7"; KEYS="track.pad.k_factor,track.pad.c_factor,track.ballast.k_factor,track.ballast.c_factor"; LABEL=Kp; NB=12
else
  SC=$WORK/light.toml; NA=3; SHARDS="3"; KEYS="bridge.EI_factor,bridge.mass_per_m_factor"; LABEL=EI; NB=8
  light_span "$SC" '"hslm:A1"'
  cat >> "$SC" <<EOF
[sweep]
speed_min_mps = 80.0
speed_max_mps = 90.0
n_speeds = 2
mode = "sample"
n_samples = 4
[[sweep.variants]]
key = "bridge.EI"
label = "EI"
distribution = "lognormal"
mean = 1.0
sd = 0.1
[[sweep.variants]]
key = "bridge.mass_per_m"
distribution = "uniform"
low = 0.9
high = 1.1
EOF
fi

# A: plain samples, one per shard at N = 7.
A=(--set sweep.n_samples=$NA --set sweep.n_speeds=2 --set sweep.batch=2)
expect 0 "$NA samples (" -- "$VIADUCT" sweep "$SC" "${A[@]}" --out "$WORK/a-one"
expect 0 "train,station,n,acc_mean_mps2,acc_sd_mps2,acc_p5_mps2,acc_p50_mps2,acc_p95_mps2,p_exceed,p_exceed_se,p_exceed_upper95" -- head -1 "$WORK/a-one/peak_percentiles.csv"
expect 0 "train,speed_kmh,station,n,acc_mean_mps2" -- head -1 "$WORK/a-one/percentiles.csv"
expect 0 "sample,block,$KEYS" -- head -1 "$WORK/a-one/samples.csv"
expect 0 "sample,train,speed_kmh,station,max_abs_acc_mps2,max_abs_disp_m" -- head -1 "$WORK/a-one/sample_peaks.csv"
stations=$(tail -n +2 "$WORK/a-one/sample_peaks.csv" | cut -d, -f4 | sort -u | wc -l)
expect 0 "$((NA * 2 * stations + 1))" -- wc -l "$WORK/a-one/sample_peaks.csv"
expect 1 "" -- grep -il "nan" "$WORK"/a-one/*.csv
expect 0 "n_samples_total = $NA" -- cat "$WORK/a-one/manifest.toml"
for n in $SHARDS; do
  dirs=()
  for k in $(seq 1 "$n"); do
    expect 0 "shard.toml" -- "$VIADUCT" sweep "$SC" "${A[@]}" --shard "$k/$n" --out "$WORK/a-$n-$k"
    dirs+=("$WORK/a-$n-$k")
  done
  expect 0 "merged $n shards ($NA samples)" -- "$VIADUCT" merge "${dirs[@]}" --out "$WORK/a-merged-$n"
  same "$WORK/a-one" "$WORK/a-merged-$n" $FILES
done
# The SLURM job array's script (scripts/cluster/sampled-array.slurm) as its tasks would run it.
for k in 1 2; do
  expect 0 "" -- env N=2 SCENARIO="$SC" OUT="$WORK/slurm" VIADUCT="$VIADUCT" SLURM_ARRAY_TASK_ID=$k \
    bash "$SRC/scripts/cluster/sampled-array.slurm" "${A[@]}"
done
expect 0 "merged 2 shards" -- "$VIADUCT" merge "$WORK/slurm/shard-1" "$WORK/slurm/shard-2" --out "$WORK/slurm/merged"
same "$WORK/a-one" "$WORK/slurm/merged" $FILES
# A shard missing, given twice, or of another study (another seed) is named.
L=${SHARDS##* }
expect 2 "shard 2/$L is missing: run it with viaduct sweep ... --shard 2/$L" -- "$VIADUCT" merge "$WORK/a-$L-1" "$WORK/a-$L-3" --out "$WORK/bad"
expect 2 "shard 1/$L is given twice" -- "$VIADUCT" merge "$WORK/a-$L-1" "$WORK"/a-$L-* --out "$WORK/bad"
"$VIADUCT" sweep "$SC" "${A[@]}" --set sweep.seed=9 --shard 2/$L --out "$WORK/a-other" --quiet
expect 2 "is of another study" -- "$VIADUCT" merge "$WORK/a-$L-1" "$WORK/a-other" "$WORK/a-$L-3" --out "$WORK/bad"
expect 2 "has no shard.toml" -- "$VIADUCT" merge "$WORK/a-one" --out "$WORK/bad"

# B: Saltelli's design (Sobol indices) in 2 shards; a run killed after its first batch, resumed.
B=(--set sweep.n_samples=2 --set sweep.n_speeds=2 --set sweep.sensitivity=true --set sweep.batch=1)
expect 0 "sensitivity.csv" -- "$VIADUCT" sweep "$SC" "${B[@]}" --out "$WORK/b-one"
expect 0 "train,station,quantity,key,label,n_base,S,S_lo,S_hi,ST,ST_lo,ST_hi" -- head -1 "$WORK/b-one/peak_sensitivity.csv"
expect 0 "2,AB_$LABEL," -- cat "$WORK/b-one/samples.csv"
"$VIADUCT" sweep "$SC" "${B[@]}" --shard 1/2 --out "$WORK/b-1" --quiet
"$VIADUCT" sweep "$SC" "${B[@]}" --shard 2/2 --out "$WORK/b-2" --quiet
expect 0 "merged 2 shards ($NB samples)" -- "$VIADUCT" merge "$WORK/b-2" "$WORK/b-1" --out "$WORK/b-merged"
same "$WORK/b-one" "$WORK/b-merged" $FILES sensitivity.csv peak_sensitivity.csv
"$VIADUCT" sweep "$SC" "${B[@]}" --out "$WORK/b-int" --quiet &
pid=$!
for _ in $(seq 1 2400); do
  grep -q "done = [1-9]" "$WORK/b-int/sample_progress.toml" 2>/dev/null && break
  sleep 0.05
done
kill -9 "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
if [ -f "$WORK/b-int/sample_progress.toml" ]; then
  expect 0 "sample_peaks.csv.partial" -- ls "$WORK/b-int"
  expect 0 "resuming" -- "$VIADUCT" sweep "$SC" "${B[@]}" --out "$WORK/b-int" --resume
else  # finished before the kill (a very fast machine): nothing left to resume
  expect 2 "nothing to resume" -- "$VIADUCT" sweep "$SC" "${B[@]}" --out "$WORK/b-int" --resume
fi
same "$WORK/b-one" "$WORK/b-int" $FILES sensitivity.csv peak_sensitivity.csv

# Bad input: exit 2 naming file, line and key, or the option.
expect 2 "sweep.variants[0].sd': sd = -0.3: violated constraint sd > 0" -- "$VIADUCT" sweep "$OG" --set sweep.variants[0].sd=-0.3 --out "$WORK/bad"
expect 2 "old-guadiana-sampled.toml:63: key 'sweep.variants[1].low': a normal factor takes no low" -- "$VIADUCT" sweep "$OG" --set sweep.variants[1].distribution=normal --out "$WORK/bad"
expect 2 "sweep.variants[1].low" -- "$VIADUCT" sweep "$OG" --set sweep.variants[1].low=3.0 --out "$WORK/bad"
expect 2 "violated constraint low < high" -- "$VIADUCT" sweep "$OG" --set sweep.variants[1].low=3.0 --out "$WORK/bad"
expect 2 "expected K/N with 1 <= K <= N, got '3/2'" -- "$VIADUCT" sweep "$OG" --shard 3/2 --out "$WORK/bad"
expect 2 "nothing to resume" -- "$VIADUCT" sweep "$OG" --resume --out "$WORK/empty"
mkdir -p "$WORK/damaged" && echo "done = = 3" > "$WORK/damaged/sample_progress.toml"
expect 2 "damaged/sample_progress.toml" -- "$VIADUCT" sweep "$OG" --resume --out "$WORK/damaged"
expect 2 "--load-effects is not available for sampled studies" -- "$VIADUCT" sweep "$OG" --load-effects --out "$WORK/bad"
expect 2 "--resume applies to sampled studies" -- "$VIADUCT" sweep "$SRC/scenarios/old-guadiana-sensitivity.toml" --resume --out "$WORK/bad"

if [ "$MPI" = mpi ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
  expect 0 "over 2 MPI ranks" -- mpirun -n 2 "$VIADUCT" sweep "$SC" "${A[@]}" --out "$WORK/a-mpi"
  same "$WORK/a-one" "$WORK/a-mpi" $FILES
  expect 0 "mpi_ranks = 2" -- cat "$WORK/a-mpi/manifest.toml"
  expect 0 "over 2 MPI ranks" -- mpirun -n 2 "$VIADUCT" sweep "$SC" "${B[@]}" --out "$WORK/b-mpi"
  same "$WORK/b-one" "$WORK/b-mpi" $FILES sensitivity.csv peak_sensitivity.csv
  expect 2 "only viaduct sweep on a sampled study" -- mpirun -n 2 "$VIADUCT" check "$OG"
  expect 2 "or in shards (--shard K/N)" -- mpirun -n 2 "$VIADUCT" sweep "$SRC/scenarios/hslm-simply-supported.toml" --out "$WORK/bad"
fi
finish
