#!/usr/bin/env bash
# Measures the speed/accuracy ladder (`viaduct tradeoff`) on the two shipped studies and writes
# docs/accuracy.md with the tables, the presets' measured errors and the commands.
#   scripts/measure/accuracy.sh [--quick]
# --quick: 4 speeds and one train each (a smoke run; does not write the docs).
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/measure/lib.sh
quick=0
[ "${1:-}" = "--quick" ] && quick=1
release_build
O=out/accuracy
fresh_dir "$O"
og_args=(--speeds 60)
hslm_args=(--speeds 29)
if [ "$quick" -eq 1 ]; then
  og_args=(--speeds 4)
  hslm_args=(--speeds 4 --set 'train.files=["data/trains/hslm/A1.toml"]')
  echo "quick mode: the IDA run below still takes a minute" >&2
fi
echo "accuracy: Old Guadiana" >&2
"$V" tradeoff scenarios/old-guadiana-sensitivity.toml "${og_args[@]}" --threads 2 --quiet --out "$O/og"
echo "accuracy: HSLM" >&2
"$V" tradeoff scenarios/hslm-simply-supported.toml "${hslm_args[@]}" --threads 2 --quiet --out "$O/hslm"
# IDA costs seconds per case here: its rungs on HSLM-A1 at 5 speeds only.
echo "accuracy: HSLM-A1 with IDA" >&2
"$V" tradeoff scenarios/hslm-simply-supported.toml --speeds 5 --with-ida --set 'train.files=["data/trains/hslm/A1.toml"]' \
  --threads 2 --quiet --out "$O/hslm-ida"
/usr/bin/python3 scripts/plot/plot_tradeoff.py "$O/og" >/dev/null
/usr/bin/python3 scripts/plot/plot_tradeoff.py "$O/hslm" >/dev/null
/usr/bin/python3 scripts/plot/plot_tradeoff.py "$O/hslm-ida" >/dev/null
# Presets: the full studies with each preset, errors against the reference rung of the tradeoff
# (same speeds: the tradeoff's speeds are all 60 of Old Guadiana; HSLM every 10 km/h).
preset_cell() {  # preset tradeoff.csv -> "x % acc, y % disp, t s"
  awk -F, -v p="preset $1 " 'index($1, p) == 1 {printf "%.2f %% acc, %.3f %% disp, %.2f s", 100*$10, 100*$11, $8}' "$2"
}
table() {  # tradeoff.csv -> markdown rows
  awk -F, 'NR>1 { printf "| %s | %s | %s | %s | %.3g | %.2f %% | %.3f %% |\n", $1, ($5==""?"—":$5), ($6==""?"—":$6), ($7==""?"—":$7), $8, 100*$10, 100*$11 }' "$1"
}
if [ "$quick" -eq 1 ]; then
  table "$O/og/tradeoff.csv"
  table "$O/hslm/tradeoff.csv"
  exit 0
fi
cat > docs/accuracy.md <<DOC
# Speed against accuracy

Measured by \`scripts/measure/accuracy.sh\` on $(date -u +%Y-%m-%d) ($(nproc) cores, release preset, 2 threads),
with \`viaduct tradeoff\`: each rung runs the scenario's speeds and trains (not its sensitivity
variants); its error is the largest difference of the maximum-response envelope over speeds,
divided by the largest reference value of the same (train, station) curve, then the worst curve.
Accelerations are filtered as the scenario says, deflections are not. The reference is Newmark at
a quarter of the scenario's step. Wall times are those of the whole sweep of the rung (model
preparation — assembly, eigenproblem — included) and are one run each on a shared machine.

## Methods

- **newmark**: average-acceleration Newmark on every DOF, fixed step; in sweeps four speeds of a
  train share one sparse LDLᵀ factorisation and run in SIMD lanes (same answers as one at a time).
  Second order; its error is a period elongation that shifts resonance peaks.
- **modal**: modes of the assembled model (track included) up to a frequency; each modal equation
  is solved exactly per step for a load varying linearly between samples (no stability limit, no
  period error). Damping that couples the modes (the track's pad and ballast dashpots; the
  Old Guadiana model's coupling index reaches 0.46 below 100 Hz) is kept: the reduced system is
  diagonalised in complex modes instead of dropping the off-diagonal terms — dropping them
  overestimated the Old Guadiana envelope by up to 70 % at low speeds. **+sc**: static correction
  (mode-acceleration): the dropped modes' quasi-static response is added to deflections, and,
  for moving axles, its second time derivative (v² times the curvature of the tabulated
  influence lines) to accelerations. **Damping vectors** (\`modal.damping_vectors\`, 1 block by
  default; rungs marked dv=0 go without): with discrete dashpots the low complex modes are not in
  the span of the low undamped modes — to first order complex mode j gains iωⱼ R C φⱼ, R the
  flexibility of the dropped modes — so R C φⱼ are appended (M-orthonormalised, Rayleigh–Ritz;
  the modes themselves unchanged, nothing added for classical damping). They are seeded by as
  many of the lowest modes as keep every Ritz pair below 80 % of the output's Nyquist frequency
  π/dt: a pair above it aliases into the filter's band (the 180 Hz basis at dt = 1 ms had pairs to
  1.3 kHz: 23 % off with them, 3 % with them dropped, 0.85 % seeded by fewer modes). They bring
  the modal error of the doubled-pad-damping variant (Cp ×2) from 1.5 % to 0.4 % at 90 Hz.
- **modal in sweeps**: the fused kernel — each train folded once into one piecewise cubic of the
  head position per load channel (exact), four speeds in SIMD lanes, classical modes or complex
  coordinates (split real arithmetic); with a filter the station accelerations are recorded and
  filtered as a single run's are, else only running maxima are kept. The same envelope as the
  general path to 1e-9, several times faster (docs/benchmarks.md).
- **maxima**: of filtered accelerations, taken between samples (the vertex of the parabola through
  the largest sample and its neighbours; a sampled 35 Hz crest is up to 0.6 % low at 1 ms); raw
  accelerations and deflections: the largest sample.
- **unit-response**: one run of a unit axle per speed, shifted and scaled over every train's axles
  (4-point cubic interpolation of the fractional shifts); exact for linear models, so its error is
  the interpolation's plus that of the method underneath.
- **ida**: SUNDIALS IDA (variable-order BDF, KLU), outputs every analysis.dt, stopped and restarted
  at every axle entry and exit. Adaptive in time, but the error test sees the whole state,
  including the kHz modes a fine beam mesh has and every element crossing excites: it takes
  small steps everywhere and is the slowest rung by far at useful tolerances.

## Old Guadiana (\`scenarios/old-guadiana-sensitivity.toml\`, reference variant, 60 speeds, 528 DOFs)

Band edge f_c = 60 Hz (band-pass 1–60 Hz). Command:
\`viaduct tradeoff scenarios/old-guadiana-sensitivity.toml --speeds 60 --threads 2\`.

| rung | modes up to [Hz] | modes | static correction | wall [s] | acceleration envelope error | deflection envelope error |
|---|---|---|---|---|---|---|
$(table "$O/og/tradeoff.csv")

## Single span, HSLM-A1…A10 (\`scenarios/hslm-simply-supported.toml\`, 29 speeds every 10 km/h, 60 DOFs)

Band edge f_c = 45 Hz (low-pass; EN 1991-2: max(30 Hz, 1.5 f1, f3)). Command:
\`viaduct tradeoff scenarios/hslm-simply-supported.toml --speeds 29 --threads 2\`.

| rung | modes up to [Hz] | modes | static correction | wall [s] | acceleration envelope error | deflection envelope error |
|---|---|---|---|---|---|---|
$(table "$O/hslm/tradeoff.csv")

IDA, HSLM-A1 only, 5 speeds (140, 210, 280, 350, 420 km/h), against the same Newmark reference:
\`viaduct tradeoff scenarios/hslm-simply-supported.toml --speeds 5 --with-ida --set 'train.files=["data/trains/hslm/A1.toml"]'\`

| rung | modes up to [Hz] | modes | static correction | wall [s] | acceleration envelope error | deflection envelope error |
|---|---|---|---|---|---|---|
$(table "$O/hslm-ida/tradeoff.csv" | grep -E '^[|] (ida|newmark)')

Plots: \`scripts/plot/plot_tradeoff.py out/accuracy/og\` and \`.../hslm\` (error against wall time, log–log,
Pareto front).

## Presets

\`analysis.preset\` sets the method, step and modal basis from the band edge f_c (filter.high_hz, or
30 Hz without a filter); keys given explicitly override it. Their rungs in the tables above:

| preset | settings | Old Guadiana (f_c = 60 Hz) | HSLM span (f_c = 45 Hz) |
|---|---|---|---|
| \`fast\` | modal, modes up to 1.5 f_c, +sc, dt = 1/(16 f_c) | $(preset_cell fast "$O/og/tradeoff.csv") | $(preset_cell fast "$O/hslm/tradeoff.csv") |
| \`default\` | modal, modes up to 2 f_c, +sc, dt = 1/(16 f_c) | $(preset_cell default "$O/og/tradeoff.csv") | $(preset_cell default "$O/hslm/tradeoff.csv") |
| \`reference\` | Newmark, dt = 1/(80 f_c) | the reference itself (0.21 ms ≈ 0.25 ms) | the reference itself (0.28 ms ≈ 0.25 ms) |

(wall time of the whole sweep of the tradeoff's speeds and trains, 2 threads). The presets' step
is coarser than the scenarios' 1 ms (1.04 ms at 60 Hz, 1.39 ms at 45 Hz): the modal step is exact,
the step only samples the load and the output.

Filtering. Simulated accelerations start at rest and are cut free_vibration_s after the last
axle: they are filtered as zero outside the record (\`signal::filtfilt_from_rest\`: the backward
pass starts in the state of the forward pass's exact free ringing beyond the end). Until
2026-12-01 they were filtered as measured records are (SciPy's sosfiltfilt: 21 samples of odd
extension at each end, a length in time that changes with dt), and with the 1 Hz edge (poles
decaying in 0.6 s) that moved maxima a second before the end by per cent: on the Old Guadiana
model at 323 km/h, ending the record 50 ms later moved the filtered peak from 3.460 to 3.526 m/s²,
and 1.6 points of the 1.9 % between dt = 1 ms and 0.0625 ms were that edge, not the integrator.
Errors now converge as the methods do (Newmark: dt²).

The whole Old Guadiana sensitivity study (13 models × 60 speeds, against Newmark at 0.1 ms) with
each preset and the bases around them is measured by \`scripts/measure/bench.sh\` (docs/benchmarks.md).
There the modal error is largest at high speed on the pad and ballast variants: the axles pass
the sleepers at v/0.6 m (67–167 Hz over the sweep) and excite track modes above the basis whose
response reaches the deck's band. It does not fall steadily with the basis (with damping
vectors: 90 Hz 1.4 %, 120 Hz 0.7 %, 180 Hz 0.85 %), so the presets are the measured best.

## Stability at the extremes

Tested (\`tests/verification/test_extremes.cpp\`, \`test_modal_superposition.cpp\`, \`tests/unit/solve/\`):
very stiff and very soft pads, zero damping, 5 and 600 km/h, steps ×10 and ÷100 for Newmark;
modal bases from one mode to all modes (all finite and bounded; all modes reproduce Newmark to
its own error, 2e-4 of the peak); the exact modal step at ω·dt = 7; IDA from rtol 1e-2 (bounded,
inaccurate) to 1e-9 (converging to the closed form), a restart at every discontinuity, soft pads,
zero damping, 20 and 600 km/h. IDA with pads ×1e4 is stable (1.966 mm against 1.990 mm static)
but took 90 570 internal steps and 75 s for one second of simulation: the rail-on-pad modes move
to tens of kHz and the error test follows them, so that case is not in the test suite.
DOC
echo "wrote docs/accuracy.md" >&2
