#!/usr/bin/env bash
# Wall times of two viaduct binaries on the headline studies, alternating A and B in each round so
# that the machine's noise falls on both alike; prints the median of each and the ratio B/A.
# For a refactor: A = the binary before, B = after (docs/benchmarks.md rows are scripts/measure/bench.sh's).
#
#   scripts/measure/bench_ab.sh A B [ROUNDS]      (ROUNDS: default 3)
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/measure/lib.sh
[ $# -ge 2 ] || { sed -n '2,7p' "$0"; exit 2; }
A=$(realpath "$1")
B=$(realpath "$2")
rounds=${3:-3}
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
field() { sed -n "s/^$2 = //p" "$1/manifest.toml" | tr -d '"'; }
studies=(
  "hslm-3modes|sweep scenarios/hslm-simply-supported.toml --set analysis.method=\"modal\" --set modal.n_modes=3 --set filter.enabled=false --set analysis.dt=0.0005 --set analysis.free_vibration_s=2 --threads 2|sweep_wall_s"
  "og-default|sweep scenarios/old-guadiana-sensitivity.toml --set analysis.preset=\"default\" --threads 2|sweep_wall_s"
  "og-newmark-12|sweep scenarios/old-guadiana-sensitivity.toml --set sweep.n_speeds=12 --threads 2|sweep_wall_s"
  "hslm-newmark|sweep scenarios/hslm-simply-supported.toml --set 'train.files=[\"data/trains/hslm/A1.toml\",\"data/trains/hslm/A5.toml\"]' --threads 2|sweep_wall_s"
  "talgo-run|run scenarios/old-guadiana-talgo.toml|solver_wall_s"
)
printf '%-16s %10s %10s %8s\n' study "A [s]" "B [s]" "B/A"
for s in "${studies[@]}"; do
  IFS='|' read -r name cmd key <<<"$s"
  for r in $(seq "$rounds"); do
    for bin in A B; do
      exe=$A
      [ "$bin" = B ] && exe=$B
      # shellcheck disable=SC2086
      eval "\"$exe\" $cmd --quiet --out \"$W/$name-$bin-$r\""
      field "$W/$name-$bin-$r" "$key" >> "$W/$name-$bin"
    done
  done
  a=$(median < "$W/$name-A")
  b=$(median < "$W/$name-B")
  printf '%-16s %10.3f %10.3f %8.3f\n' "$name" "$a" "$b" "$(awk -v a="$a" -v b="$b" 'BEGIN{print b/a}')"
done
