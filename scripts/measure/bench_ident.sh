#!/usr/bin/env bash
# Benchmarks of the identification paths (issue #4), not tests: model FRF by direct solve, the
# simulated shaker test, stepped-sine processing, modal fit and free-decay analysis, on the Old
# Guadiana model. Writes docs/benchmarks-identification.md with the figures and the commands.
#   scripts/measure/bench_ident.sh [--repeats N]
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/measure/lib.sh
bench_start out/bench-ident "$@"
OG=scenarios/old-guadiana-talgo.toml
wall() {  # runs the command, prints its wall time [s]
  local t0 t1
  t0=$(date +%s.%N)
  "$@" >/dev/null
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f\n", b - a}'
}
med() {  # repeats the command, prints the median wall time
  for _ in $(seq "$repeats"); do wall "$@"; done | median
}
echo "bench-ident: model FRF" >&2
frf_args=(frf "$OG" --force-at 6 --f-min 1 --f-max 30 --n-freq 1161 --quiet --out "$B/frf")
f1=$(med "$V" "${frf_args[@]}" --threads 1)
f2=$(med "$V" "${frf_args[@]}" --threads 2)
echo "bench-ident: shaker test" >&2
sh_args=(shaker "$OG" --force-at 6 --stepped 8:12:0.05 --dwell-s 8 --fs-hz 100 --snr-db 40 --quiet --out "$B/test")
s1=$(wall "$V" "${sh_args[@]}")
steps=$(sed -n 's/^newmark_steps = //p' "$B/test/manifest.toml" | tr -d '"')
echo "bench-ident: processing" >&2
p1=$(med "$V" frf "$B/test/record.csv" --force force_N --method stepped --steps "$B/test/steps.csv" --quiet --out "$B/test-frf")
m1=$(med "$V" modal-fit "$B/test-frf/frf.csv" --max-order 20 --quiet --out "$B/modes")
m2=$(med "$V" modal-fit "$B/test-frf/frf.csv" --max-order 20 --no-refine --quiet --out "$B/modes-diagram")
"$V" run "$OG" --set analysis.free_vibration_s=5 --quiet --out "$B/passage"
d1=$(med "$V" decay "$B/passage/history.csv" --channel S1_mid_acc --frequency-hz 10 --quiet --out "$B/decay")
n_rec=$(($(grep -vc '^#' "$B/test/record.csv") - 1))
per_step=$(awk -v w="$s1" -v s="$steps" 'BEGIN{printf "%.1f", 1e6 * w / s}')
cat > docs/benchmarks-identification.md <<DOC
# Benchmarks: identification

Measured by \`scripts/measure/bench_ident.sh\` on $(date -u +%Y-%m-%d), $(nproc) cores, release preset, on the Old
Guadiana model (\`$OG\`, 528 DOFs with the track). Medians of $repeats runs (the shaker test: one run);
wall time of the whole command (model build and I/O included).

| what | command | wall time |
|---|---|---|
| model FRF, 1161 frequencies 1–30 Hz, 3 responses, 1 thread | \`viaduct ${frf_args[*]} --threads 1\` | $f1 s |
| the same, 2 threads | \`… --threads 2\` | $f2 s |
| simulated stepped-sine test, 81 dwells of 8 s, $steps Newmark steps ($per_step µs each), $n_rec samples | \`viaduct ${sh_args[*]}\` | $s1 s |
| stepped-sine processing of that record (81 fits × 4 channels) | \`viaduct frf RECORD --force force_N --method stepped --steps steps.csv\` | $p1 s |
| modal fit: peak picking, circle fit, LSCF orders 2–20, refinement and split test | \`viaduct modal-fit frf.csv --max-order 20\` | $m1 s |
| the same without refinement and split test | \`… --no-refine\` | $m2 s |
| free decay of one passage record | \`viaduct decay history.csv --channel S1_mid_acc --frequency-hz 10\` | $d1 s |
DOC
echo "wrote docs/benchmarks-identification.md"
