#!/usr/bin/env bash
# The SIMD kernels give the same numbers on every instruction set (src/solve/lanes.hpp: no FMA
# contraction, every lane the same operations): sweeps through the complex-modes peaks kernel
# (eight cases a pass with AVX-512, four with AVX2 or the baseline build), the classical one
# (its general loops eight cases a pass with AVX-512 too, its fixed-size ones four) and batched Newmark, run with VIADUCT_SIMD unset, avx2 and
# baseline, write the same files byte for byte. A machine without AVX-512 compares what it has.
# A wrong VIADUCT_SIMD stops the command (exit 2) naming the variable.
. "$(dirname "$0")/lib.sh"
# levels NAME FILES -- sweep arguments...: the sweep at each level, its files compared.
levels() {
  local name=$1 files=$2 s
  shift 3
  for s in native avx2 baseline; do
    expect 0 "" -- env VIADUCT_SIMD="$([ $s = native ] || echo $s)" "$VIADUCT" sweep "$@" -q --threads 2 --out "$WORK/$name-$s"
  done
  for s in avx2 baseline; do
    # shellcheck disable=SC2086
    same "$WORK/$name-native" "$WORK/$name-$s" $files
  done
}

# Old Guadiana with its ballasted track: discrete dashpots, so complex modes (with the damping
# vectors and the static correction), the filter's recorded histories, load effects and their
# sums; 11 speeds: a full pass of eight and a partial one.
cat > "$WORK/og.toml" <<EOT
[bridge]
file = "$SRC/data/bridges/old-guadiana.toml"
[track]
file = "$SRC/data/tracks/old-guadiana-ballasted.toml"
[train]
files = ["$SRC/data/trains/artificial-20x210.toml", "hslm:A3"]
load_factor = 0.5
[analysis]
method = "modal"
dt = 0.002
free_vibration_s = 0.5
[modal]
max_frequency_hz = 60.0
[filter]
band = "lowpass"
high_hz = 30.0
[[stations]]
name = "S1_mid"
span = 1
at = 0.5
[[stations]]
name = "S2_mid"
span = 2
at = 0.5
[sweep]
speed_min_mps = 40.0
speed_max_mps = 100.0
n_speeds = 11
EOT
levels complex "envelope.csv governing.csv load_effects.csv" -- "$WORK/og.toml" --load-effects
grep -q '"analysis.method" = "modal"' "$WORK/complex-native/manifest.toml" || { echo "FAIL: the complex sweep did not run modal"; n_fail=$((n_fail + 1)); }

# A single span, classical modes: the fixed-size loop (3 modes, one station, no load effects),
# the general one (31 stations of load effects along the span), and batched Newmark.
HS=$SRC/scenarios/hslm-simply-supported.toml
levels fixed "envelope.csv governing.csv" -- "$HS" --set analysis.method='"modal"' --set modal.n_modes=3 --set sweep.speed_step_kmh=40
levels along "envelope.csv governing.csv load_effects.csv" -- "$HS" --set analysis.method='"modal"' --set modal.n_modes=3 \
  --set 'stations[1].name="L"' --set stations[1].span=1 --set stations[1].every_m=0.5 --set sweep.speed_step_kmh=40 --load-effects
levels newmark "envelope.csv governing.csv" -- "$HS" --set analysis.method='"newmark"' --set sweep.speed_step_kmh=60

expect 2 "environment variable VIADUCT_SIMD = 'avx3': expected baseline, avx2 or avx512" -- \
  env VIADUCT_SIMD=avx3 "$VIADUCT" sweep "$HS" -q --out "$WORK/bad"
[ ! -e "$WORK/bad" ] || { echo "FAIL: a refused VIADUCT_SIMD left outputs"; n_fail=$((n_fail + 1)); }
finish
