#!/usr/bin/env bash
# Shards of a sweep (#16, viaduct sweep --shard K/N, viaduct merge): N = 1, 2 and 7 shards of an
# HSLM sweep, shards of a sweep with variants, a variant that fails and --load-effects, and of a
# sweep with vehicle models, all merge into the files of one process byte for byte, with its exit
# code; a missing, repeated or foreign shard is an error naming it.
. "$(dirname "$0")/lib.sh"
# shards NAME N CODE [sweep arguments...]: the sweep in one process and in N shards (exit code
# CODE each, 0 for an empty shard), then the merge (exit code CODE).
shards() {
  local name=$1 n=$2 code=$3 k dirs=()
  shift 3
  "$VIADUCT" sweep "$@" -q --out "$WORK/$name-one" 2>/dev/null
  for k in $(seq "$n" -1 1); do  # any order
    "$VIADUCT" sweep "$@" -q --shard "$k/$n" --out "$WORK/$name-$n-$k" 2>/dev/null
    dirs+=("$WORK/$name-$n-$k")
  done
  expect "$code" "" -- "$VIADUCT" merge "${dirs[@]}" -q --out "$WORK/$name-$n-merged"
}

# Argument 3: "full" (optimised build) or "light" (the sanitizers: a third of the HSLM speeds, the
# same code paths).
if [ "${3:-full}" = full ]; then
  HSLM=(--set sweep.speed_step_kmh=40 --threads 2 "$SRC/scenarios/hslm-simply-supported.toml")
  SHARD_2_OF_7="shard 2/7: cases 12 to 22 of 80"
else
  HSLM=(--set sweep.speed_step_kmh=120 --threads 2 "$SRC/scenarios/hslm-simply-supported.toml")
  SHARD_2_OF_7="shard 2/7: cases 5 to 8 of 30"
fi
for n in 1 2 7; do
  shards hslm "$n" 0 "${HSLM[@]}"
  same "$WORK/hslm-one" "$WORK/hslm-$n-merged" envelope.csv governing.csv failures.csv
done
expect 0 "$SHARD_2_OF_7" -- "$VIADUCT" sweep "${HSLM[@]}" --shard 2/7 --out "$WORK/hslm-7-2-again"
same "$WORK/hslm-7-2" "$WORK/hslm-7-2-again" envelope.csv governing.csv  # a shard reruns alone, the same

# Variants, one of which breaks its key's rule (factor 0: its cases fail, the sweep exits 1),
# with load effects: every file, and the exit code, as one process.
light_span "$WORK/variants.toml" '"hslm:A1", "hslm:A4"'
cat >> "$WORK/variants.toml" <<EOT
[[stations]]
name = "quarter"
span = 1
at = 0.25
[sweep]
speeds_kmh = [200.0, 250.0, 300.0]
mode = "one-at-a-time"
[[sweep.variants]]
key = "bridge.EI"
factors = [0.0, 0.8, 1.25]
EOT
shards variants 3 1 "$WORK/variants.toml" --load-effects
same "$WORK/variants-one" "$WORK/variants-3-merged" envelope.csv governing.csv failures.csv load_effects.csv
expect 0 "factor 0 breaks the rule" -- cat "$WORK/variants-3-merged/failures.csv"

# Vehicle models: vehicles.csv too.
shards vehicles 2 0 "$SRC/scenarios/vehicles-25m.toml" --set sweep.speed_step_kmh=120
same "$WORK/vehicles-one" "$WORK/vehicles-2-merged" envelope.csv governing.csv failures.csv vehicles.csv

# Errors name the shard.
expect 2 "shard 3/7 is missing: run it with viaduct sweep ... --shard 3/7" -- \
  "$VIADUCT" merge "$WORK"/hslm-7-{1,2,4,5,6,7} --out "$WORK/bad"
expect 2 "shard 2/7 is given twice" -- "$VIADUCT" merge "$WORK"/hslm-7-{1,2,3,4,5,6,7} "$WORK/hslm-7-2-again" --out "$WORK/bad"
expect 2 "is of another study than" -- "$VIADUCT" merge "$WORK/hslm-2-1" "$WORK/variants-3-2" --out "$WORK/bad"
"$VIADUCT" sweep "$WORK/variants.toml" -q --shard 1/3 --out "$WORK/variants-3-1-plain" 2>/dev/null
expect 2 "shard 2 ran with --load-effects, shard 1 without" -- "$VIADUCT" merge "$WORK/variants-3-1-plain" "$WORK"/variants-3-{2,3} --out "$WORK/bad"
# A shard of a sampled study among those of a sweep.
sed -e 's/mode = "one-at-a-time"/mode = "sample"\nn_samples = 2/' -e 's/factors = .*/distribution = "uniform"\nlow = 0.9\nhigh = 1.1/' \
  "$WORK/variants.toml" > "$WORK/sampled.toml"
expect 0 "" -- "$VIADUCT" sweep "$WORK/sampled.toml" -q --shard 1/3 --out "$WORK/sampled-3-1"
expect 2 "sampled-3-1 is a shard of a sampled study, $WORK/variants-3-2 of a sweep" -- \
  "$VIADUCT" merge "$WORK/variants-3-2" "$WORK/sampled-3-1" --out "$WORK/bad"
# A damaged shard.toml is an input error naming it, not a crash.
cp -r "$WORK/hslm-2-1" "$WORK/damaged" && echo "garbage = = " >> "$WORK/damaged/shard.toml"
expect 2 "damaged/shard.toml" -- "$VIADUCT" merge "$WORK/damaged" "$WORK/hslm-2-2" --out "$WORK/bad"
# A shard.toml edited by hand after its run: its manifest's checksum tells (#36; the keys' own
# checks are in tests/unit/io/test_sweep_shard.cpp).
sed -i 's/^station = /statio = /' "$WORK/hslm-2-2/shard.toml"
expect 2 "hslm-2-2: shard.toml changed since the run that wrote the manifest" -- "$VIADUCT" merge "$WORK/hslm-2-1" "$WORK/hslm-2-2" --out "$WORK/bad"
# A shard whose run did not finish (no manifest) is no shard.
cp -r "$WORK/hslm-2-1" "$WORK/unfinished" && rm "$WORK/unfinished/manifest.toml"
expect 2 "unfinished: no manifest.toml: the run that wrote this directory did not finish" -- "$VIADUCT" merge "$WORK/unfinished" "$WORK/hslm-2-2" --out "$WORK/bad"
expect 2 "has no shard.toml" -- "$VIADUCT" merge "$WORK/hslm-one" --out "$WORK/bad"
expect 2 "expected K/N with 1 <= K <= N, got '3/2'" -- "$VIADUCT" sweep "${HSLM[@]}" --shard 3/2 --out "$WORK/bad"
expect 2 "--resume applies to sampled studies" -- "$VIADUCT" sweep "${HSLM[@]}" --resume --out "$WORK/bad"
finish
