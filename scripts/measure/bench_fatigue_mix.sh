#!/usr/bin/env bash
# Benchmark of `viaduct fatigue --mix` (issue #42): EN 1991-2 Annex D's twelve fatigue trains, one a
# day each at their figures' speeds, over the Old Guadiana model with its track
# (scenarios/old-guadiana-sensitivity.toml, Newmark at 1 ms), the first span's mid-span moment:
# wall time on 2 threads (median of --repeats, default 3) and on 1 thread. Issue #42 asks <= 10 s
# on 2 threads.
#   scripts/measure/bench_fatigue_mix.sh [--repeats N]
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/measure/lib.sh
bench_start out/bench-fatigue-mix "$@"
mix=$B/all-types.toml
{
  echo 'title = "EN 1991-2 Annex D: Types 1 to 12, one a day each"'
  for n in $(seq 12); do
    v=$(sed -n 's/^# V = \([0-9]*\) km\/h.*/\1/p' "data/trains/fatigue/type$n.csv")
    printf '[[trains]]\nfile = "%s"\nper_day = 1\nspeed_kmh = %s\n' "$PWD/data/trains/fatigue/type$n.csv" "$v"
  done
} > "$mix"
now() { date +%s.%N; }
run() {  # THREADS OUT
  "$V" fatigue scenarios/old-guadiana-sensitivity.toml --mix "$mix" --channel S1_mid_moment --section-modulus-m3 0.02 \
    --detail 71 --threads "$1" --quiet --out "$2"
}
walls=()
for i in $(seq "$repeats"); do
  t0=$(now)
  run 2 "$B/t2-$i"
  walls+=("$(echo "$(now) - $t0" | bc)")
done
w2=$(printf '%s\n' "${walls[@]}" | median)
t0=$(now)
run 1 "$B/t1"
w1=$(echo "$(now) - $t0" | bc)
echo "bench_fatigue_mix: 12 trains over Old Guadiana with track: 2 threads median ${w2} s (${walls[*]}), 1 thread ${w1} s"
