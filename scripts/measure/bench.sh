#!/usr/bin/env bash
# Benchmarks (not tests): wall time of the headline studies and the accuracy bought with the
# time step. Builds the release preset, runs everything in one go on this machine, and writes
# docs/benchmarks.md with the figures and the commands that produced them.
#   scripts/measure/bench.sh [--repeats N] [--quick]
# --quick: HSLM on 3 trains, Old Guadiana on 12 speeds (a smoke run; does not write the docs).
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/measure/lib.sh
repeats=3
quick=0
while [ $# -gt 0 ]; do
  case "$1" in
    --repeats) repeats=$2; shift ;;
    --quick) quick=1 ;;
    *) echo "bench.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
release_build
B=out/bench
fresh_dir "$B"
extra_hslm=()
extra_og=()
if [ "$quick" -eq 1 ]; then
  extra_hslm=(--set 'train.files=["data/trains/hslm/A1.toml","data/trains/hslm/A5.toml","data/trains/hslm/A9.toml"]')
  extra_og=(--set sweep.n_speeds=12)
  repeats=1
fi

field() { sed -n "s/^$2 = //p" "$1/manifest.toml" | tr -d '"'; }
fmt() { printf '%.1f' "$1"; }
fmt2() { printf '%.2f' "$1"; }

# 1. wall time: median of N runs each, for 1 and 2 threads
time_runs() {  # name scenario threads runs args...
  local name=$1 scen=$2 threads=$3 runs=$4
  shift 4
  for i in $(seq "$runs"); do
    "$V" sweep "$scen" --threads "$threads" --quiet --out "$B/$name-t$threads-$i" "$@"
    field "$B/$name-t$threads-$i" sweep_wall_s
  done | median
}
echo "bench: HSLM sweep" >&2
h2=$(time_runs hslm scenarios/hslm-simply-supported.toml 2 "$repeats" "${extra_hslm[@]}")
h1=$(time_runs hslm scenarios/hslm-simply-supported.toml 1 1 "${extra_hslm[@]}")
echo "bench: Old Guadiana sensitivity" >&2
o2=$(time_runs og scenarios/old-guadiana-sensitivity.toml 2 "$repeats" "${extra_og[@]}")
o1=$(time_runs og scenarios/old-guadiana-sensitivity.toml 1 1 "${extra_og[@]}")

hs=$B/hslm-t2-1
os=$B/og-t2-1
h_cases=$(field "$hs" n_cases); h_steps=$(field "$hs" n_steps_total); h_dofs=$(field "$hs" n_dofs_reference)
o_cases=$(field "$os" n_cases); o_steps=$(field "$os" n_steps_total); o_dofs=$(field "$os" n_dofs_reference)
o_var=$(field "$os" n_variants)

# 2. accuracy against the time step (Old Guadiana reference variant, all speeds)
echo "bench: time-step convergence" >&2
dts=(0.002 0.001 0.0005 0.00025 0.0001)
for dt in "${dts[@]}"; do
  "$V" sweep scenarios/old-guadiana-sensitivity.toml --set analysis.dt=$dt --set sweep.mode=reference \
    --threads 2 --quiet --out "$B/dt-$dt" "${extra_og[@]}"
done
conv_rows=""
for dt in 0.002 0.001 0.0005 0.00025; do
  row=$(awk -F, -v dt="$dt" '
    FNR==1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { v=$c["speed_kmh"]; s=$c["station"]; x=$c["max_abs_acc_mps2"]; y=$c["max_abs_disp_m"] }
    NR==FNR { a[v","s]=x; d[v","s]=y; if (x>m) m=x; if (y>md) md=y; next }
    { k=v","s; e=x-a[k]; if (e<0) e=-e; if (e>me) me=e; if (e/a[k]>mr) mr=e/a[k];
      f=y-d[k]; if (f<0) f=-f; if (f>mf) mf=f }
    END { printf "| %s ms | %.3f | %.2f %% | %.2f %% | %.3f %% |", dt*1000, me, 100*me/m, 100*mr, 100*mf/md }' \
    "$B/dt-0.0001/envelope.csv" "$B/dt-$dt/envelope.csv")
  wall=$(field "$B/dt-$dt" sweep_wall_s)
  conv_rows+="$row $(fmt "$wall") |"$'\n'
done
wall_ref=$(field "$B/dt-0.0001" sweep_wall_s)

# 3. what modal damping costs: the same sweeps with Rayleigh damping of equal ratios (1 thread)
echo "bench: cost of modal damping" >&2
damping_rows=""
damp() {  # label scenario f1 f2 ratio args...
  local label=$1 scen=$2 f1=$3 f2=$4 z=$5
  shift 5
  local w=()
  for kind in modal rayleigh; do
    "$V" sweep "$scen" --threads 1 --quiet --out "$B/damp-$label-$kind" --set bridge.damping.kind=$kind \
      --set bridge.damping.f1_hz="$f1" --set bridge.damping.ratio1="$z" --set bridge.damping.f2_hz="$f2" \
      --set bridge.damping.ratio2="$z" "$@"
    w+=("$(field "$B/damp-$label-$kind" sweep_wall_s)")
  done
  damping_rows+="| $label | $(fmt "${w[0]}") | $(fmt "${w[1]}") | $(awk -v a="${w[0]}" -v b="${w[1]}" 'BEGIN{printf "%.2f", a/b}') |"$'\n'
}
damp "HSLM-A1, 281 speeds" scenarios/hslm-simply-supported.toml 5 45 0.0135 --set 'train.files=["data/trains/hslm/A1.toml"]'
damp "Old Guadiana reference, 60 speeds" scenarios/old-guadiana-sensitivity.toml 10 60 0.01565 --set sweep.mode=reference "${extra_og[@]}"

# 4. records and signal processing at field-campaign size (one thread)
echo "bench: records and signal processing" >&2
sb=$(build/release/viaduct_signal_bench --minutes 10 --channels 18 --fs 4096 --csv-mb 100 --dir "$B")
sig() { awk -v k="$1" '$1 == k { print $2 }' <<<"$sb"; }

# 5. fast paths (issue #5): modal superposition and unit-response superposition
echo "bench: fast paths" >&2
env_err() {  # ref_dir dir -> "acc_err disp_err": worst (variant, train, station) curve, relative to its peak
  # Columns by name (a sweep with variants has KEY_factor columns after `variant`).
  awk -F, 'FNR==1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
           { k=$c["variant"]","$c["train"]","$c["station"]; key=k","$c["speed_kmh"];
             x=$c["max_abs_acc_mps2"]; y=$c["max_abs_disp_m"] }
           NR==FNR { a[key]=x; d[key]=y; if (x>pa[k]) pa[k]=x; if (y>pd[k]) pd[k]=y; next }
           { if (!(key in a)) next;
             e=x-a[key]; if (e<0) e=-e; if (pa[k]>0 && e/pa[k]>ea) ea=e/pa[k];
             f=y-d[key]; if (f<0) f=-f; if (pd[k]>0 && f/pd[k]>ed) ed=f/pd[k] }
           END { printf "%.3g %.3g", ea, ed }' "$1/envelope.csv" "$2/envelope.csv"
}
pct() { awk -v x="$1" 'BEGIN{printf "%.3f %%", 100*x}'; }
# (a) HSLM-A1…A10 × 281 speeds, 3 modes, 2000 Hz output, 2 s of free vibration, no filter (the
#     three modes are the frequency limit); reference: the same modal model at 20 kHz.
hslm_modal=(--set 'analysis.method="modal"' --set modal.n_modes=3 --set analysis.free_vibration_s=2
            --set filter.enabled=false)
hm2=$(time_runs hslm-modal scenarios/hslm-simply-supported.toml 2 "$repeats" "${hslm_modal[@]}" --set analysis.dt=0.0005 "${extra_hslm[@]}")
hm1=$(time_runs hslm-modal scenarios/hslm-simply-supported.toml 1 1 "${hslm_modal[@]}" --set analysis.dt=0.0005 "${extra_hslm[@]}")
"$V" sweep scenarios/hslm-simply-supported.toml "${hslm_modal[@]}" --set analysis.dt=0.00005 "${extra_hslm[@]}" \
  --threads 2 --quiet --out "$B/hslm-modal-ref"
read -r hm_ea hm_ed <<<"$(env_err "$B/hslm-modal-ref" "$B/hslm-modal-t2-1")"
hm_steps=$(field "$B/hslm-modal-t2-1" n_steps_total)
# the same 3-mode envelope against the full model (Newmark, 0.25 ms, the scenario's 45 Hz low-pass)
"$V" sweep scenarios/hslm-simply-supported.toml --set analysis.dt=0.00025 --set analysis.free_vibration_s=2 \
  "${extra_hslm[@]}" --threads 2 --quiet --out "$B/hslm-full-ref"
read -r hf_ea hf_ed <<<"$(env_err "$B/hslm-full-ref" "$B/hslm-modal-t2-1")"
hf_wall=$(field "$B/hslm-full-ref" sweep_wall_s)
# (b) Old Guadiana sensitivity, all variants: Newmark steps and presets against Newmark at 0.1 ms
#     (second order: 0.25 ms is still ~1 % off on the undamped-pad curve, see the rows)
og_rows=""
"$V" sweep scenarios/old-guadiana-sensitivity.toml --set analysis.dt=0.0001 "${extra_og[@]}" --threads 2 --quiet \
  --out "$B/og-ref"
og_ref_wall=$(field "$B/og-ref" sweep_wall_s)
read -r nm_ea nm_ed <<<"$(env_err "$B/og-ref" "$B/og-t2-1")"
og_rows+="| Newmark, dt = 1 ms (the shipped setting) | $(fmt "$o2") | $(pct "$nm_ea") | $(pct "$nm_ed") |"$'\n'
for dt in 0.0005 0.00025; do
  w=$(time_runs "og-nm$dt" scenarios/old-guadiana-sensitivity.toml 2 1 --set analysis.dt=$dt "${extra_og[@]}")
  read -r ea ed <<<"$(env_err "$B/og-ref" "$B/og-nm$dt-t2-1")"
  og_rows+="| Newmark, dt = $(awk -v d=$dt 'BEGIN{print d*1000}') ms | $(fmt "$w") | $(pct "$ea") | $(pct "$ed") |"$'\n'
done
for preset in fast default; do
  w=$(time_runs "og-$preset" scenarios/old-guadiana-sensitivity.toml 2 "$repeats" --set "analysis.preset=\"$preset\"" "${extra_og[@]}")
  read -r ea ed <<<"$(env_err "$B/og-ref" "$B/og-$preset-t2-1")"
  og_rows+="| modal, preset \`$preset\` | $(fmt "$w") | $(pct "$ea") | $(pct "$ed") |"$'\n'
done
# the bases around the presets: 3 f_c with damping vectors, 1.5 and 2 f_c without them
for cfg in "180 1" "90 0" "120 0"; do
  read -r fmax dv <<<"$cfg"
  w=$(time_runs "og-m$fmax-dv$dv" scenarios/old-guadiana-sensitivity.toml 2 1 --set 'analysis.preset="fast"' \
      --set modal.max_frequency_hz=$fmax --set modal.damping_vectors=$dv "${extra_og[@]}")
  read -r ea ed <<<"$(env_err "$B/og-ref" "$B/og-m$fmax-dv$dv-t2-1")"
  og_rows+="| modal $fmax Hz, $([ "$dv" = 1 ] && echo "damping vectors" || echo "no damping vectors") | $(fmt "$w") | $(pct "$ea") | $(pct "$ed") |"$'\n'
done
# (c) cost against DOFs (track length, rail elements per bay) and against train length, one case
dof_rows=""
for per_bay in 1 2; do
  for len in 10 20 40 80; do
    row="| $len m | $per_bay |"
    for m in newmark modal; do
      d="$B/dof-$len-$per_bay-$m"
      "$V" run scenarios/old-guadiana-sensitivity.toml --set run.speed_kmh=288 --set track.approach_length=$len \
        --set track.exit_length=$len --set track.rail_elements_per_bay=$per_bay --set "analysis.method=\"$m\"" \
        --set modal.max_frequency_hz=180 --quiet --out "$d"
      [ "$m" = newmark ] && row+=" $(field "$d" n_dofs) |"
      row+=" $(awk -v a="$(field "$d" solver_wall_s)" 'BEGIN{printf "%.3f", a}') |"
      [ "$m" = modal ] && row+=" $(field "$d" n_modes) | $(awk -v a="$(field "$d" wall_s)" -v b="$(field "$d" solver_wall_s)" 'BEGIN{printf "%.2f", a-b}') |"
    done
    dof_rows+="$row"$'\n'
  done
done
train_rows=""
for n in 5 10 20 40 80; do
  printf 'name = "regular-%s"\nkind = "regular"\nn_axles = %s\nspacing = 18.0\naxle_load_kN = 210.0\n' "$n" "$n" > "$B/train-$n.toml"
  row="| $n |"
  for m in newmark modal; do
    d="$B/train-$n-$m"
    "$V" run scenarios/old-guadiana-sensitivity.toml --set run.speed_kmh=288 --set "train.files=[\"$PWD/$B/train-$n.toml\"]" \
      --set "analysis.method=\"$m\"" --set modal.max_frequency_hz=180 --quiet --out "$d"
    row+=" $(awk -v a="$(field "$d" solver_wall_s)" 'BEGIN{printf "%.3f", a}') |"
  done
  train_rows+="$row"$'\n'
done
# (d) ten trains on the track model: direct against unit-response superposition (10 speeds)
hslm_on_og=(--set 'train.files=["data/trains/hslm/A1.toml","data/trains/hslm/A2.toml","data/trains/hslm/A3.toml","data/trains/hslm/A4.toml","data/trains/hslm/A5.toml","data/trains/hslm/A6.toml","data/trains/hslm/A7.toml","data/trains/hslm/A8.toml","data/trains/hslm/A9.toml","data/trains/hslm/A10.toml"]'
            --set train.load_factor=0.5 --set sweep.mode=reference --set sweep.n_speeds=10)
unit_rows=""
for cfg in "newmark direct" "newmark unit-response" "modal unit-response"; do
  read -r m sp <<<"$cfg"
  d="$B/unit-$m-$sp"
  "$V" sweep scenarios/old-guadiana-sensitivity.toml "${hslm_on_og[@]}" --set "analysis.method=\"$m\"" \
    --set "analysis.superposition=\"$sp\"" --set modal.max_frequency_hz=180 --threads 2 --quiet --out "$d"
  if [ "$cfg" = "newmark direct" ]; then e="(reference)"; else read -r ea ed <<<"$(env_err "$B/unit-newmark-direct" "$d")"; e="$(pct "$ea") / $(pct "$ed")"; fi
  unit_rows+="| $m, $sp | $(fmt "$(field "$d" sweep_wall_s)") | $e |"$'\n'
done

if [ "$quick" -eq 1 ]; then
  echo "$sb"
  echo "quick: HSLM 1 thread $h1 s, 2 threads $h2 s; Old Guadiana 1 thread $o1 s, 2 threads $o2 s"
  printf '%s' "$conv_rows" "$damping_rows" "$og_rows" "$dof_rows" "$train_rows" "$unit_rows"
  echo "HSLM modal: 1 thread $hm1 s, 2 threads $hm2 s, error $hm_ea / $hm_ed, vs full $hf_ea / $hf_ed"
  exit 0
fi

ratio() { awk -v a="$1" -v b="$2" 'BEGIN{printf "%.2f", a/b}'; }
per_step() { awk -v w="$1" -v s="$2" -v t="$3" 'BEGIN{printf "%.1f", 1e6*w*t/s}'; }
cat > docs/benchmarks.md <<DOC
# Benchmarks

Measured by \`scripts/measure/bench.sh\` on $(date -u +%Y-%m-%d), $(nproc) cores ($(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1)),
release preset, viaduct $($V --version | cut -d' ' -f2). Speed is measured here, never asserted in tests. The machine
is shared and noisy: 2-thread wall times are medians of $repeats runs, 1-thread times one run each
(one to two minutes apiece); the thread ratio comes from the same session. Identification paths
(model FRF, shaker test, modal fit, decay): [benchmarks-identification.md](benchmarks-identification.md)
(\`scripts/measure/bench_ident.sh\`). Model updating: the 3-parameter fit of the Old Guadiana model to one
record takes $(sed -n 's/^| Newmark, dt = 1 ms (default) | 2 | \([0-9.]*\) .*/\1/p' docs/benchmarks-fitting.md) s on 2 threads (target < 60 s), [benchmarks-fitting.md](benchmarks-fitting.md)
(\`scripts/measure/bench_fit.sh\`). The EN 1991-2 assessment (\`viaduct assess\`): [benchmarks-assess.md](benchmarks-assess.md)
(\`scripts/measure/bench_assess.sh\`) Sampled studies (time per case, memory, threads, shards, MPI ranks):
[benchmarks-sampled.md](benchmarks-sampled.md) (\`scripts/measure/sampled_scaling.py\`).

## Studies

| study | cases | DOFs | time steps (all cases) | 1 thread [s] | 2 threads [s] | speed-up | µs per step and thread |
|---|---|---|---|---|---|---|---|
| HSLM-A1…A10 × 140–420 km/h every 1 km/h, 15 m span, no track (\`scenarios/hslm-simply-supported.toml\`) | $h_cases | $h_dofs | $h_steps | $(fmt "$h1") | $(fmt "$h2") | $(ratio "$h1" "$h2") | $(per_step "$h2" "$h_steps" 2) |
| Old Guadiana sensitivity: $o_var distinct models (16 curves, the four factor-1 curves are one reference) × 60 speeds, full track model (\`scenarios/old-guadiana-sensitivity.toml\`) | $o_cases | $o_dofs | $o_steps | $(fmt "$o1") | $(fmt "$o2") | $(ratio "$o1" "$o2") | $(per_step "$o2" "$o_steps" 2) |

Commands: \`build/release/viaduct sweep SCENARIO --threads N\` (wall time from \`sweep_wall_s\` in
the manifest: model assembly, integration, filtering and envelopes). Time step 1 ms, Newmark
average acceleration. A sweep runs the speeds of one train four at a time through
\`solve::newmark_batch\`: one sparse LDLᵀ factorisation per batch, and every product and triangular
substitution done on the four cases at once (one AVX2 operation per matrix entry where the
processor has it, two SSE2 ones otherwise), with partial sums so that the chains of dependent
additions do not set the pace. The \`µs per step\` column counts each case's steps.

Where the time goes: every step does two sparse products (C v, K u) and one sparse LDLᵀ solve.
Modal damping of the bridge (one ratio for every span mode) makes C dense within each span,
which makes both the products and the factor denser. Measured: the same sweeps with Rayleigh
damping of the same ratio at two frequencies (1 thread, wall seconds):

| sweep | modal damping [s] | Rayleigh damping [s] | ratio |
|---|---|---|---|
$damping_rows
The fast paths below (modal superposition, unit-response superposition) avoid most of this cost.

## Accuracy bought with the time step

Old Guadiana reference model, 60 speeds × 3 stations, against the same sweep at dt = 0.1 ms
(which took $(fmt "$wall_ref") s on 2 threads). Errors of the envelope of the filtered
(1–60 Hz) deck acceleration and of the deck deflection:

| dt | max abs acc error [m/s²] | … of the peak acceleration | worst relative, any speed | max disp error, of peak | 2-thread wall [s] |
|---|---|---|---|---|---|
$conv_rows
The worst relative error is on the steep flanks of the resonance peaks, where a small
frequency shift (Newmark's period elongation) moves the curve. Newmark's convergence order is
2 (\`tests/verification/test_convergence.cpp\`): each halving of the step divides the error by
about four at twice the cost.

Command: \`viaduct sweep scenarios/old-guadiana-sensitivity.toml --set analysis.dt=DT --set sweep.mode=reference\`.

## Fast paths (modal superposition, unit-response superposition)

Errors: the worst (train, station) envelope curve, largest difference over speeds divided by
the curve's peak (\`docs/accuracy.md\` has the whole ladder).

**HSLM-A1…A10 × 281 speeds, single 15 m span, 3 modes, 2000 Hz output, 2 s free vibration**
(\`viaduct sweep scenarios/hslm-simply-supported.toml --set analysis.method='"modal"' --set modal.n_modes=3
--set analysis.dt=0.0005 --set analysis.free_vibration_s=2 --set filter.enabled=false --threads N\`):
$hm_steps samples in all; **$(fmt2 "$hm1") s on 1 thread, $(fmt2 "$hm2") s on 2 threads** (target 0.3 s;
$(awk -v w="$hm2" -v s="$hm_steps" 'BEGIN{printf "%.1f", 1e9*w*2/s}') ns per sample and thread, the whole sweep included). No history
is needed for an envelope without a filter, so the sweep runs the peaks kernel
(\`src/solve/modal_peaks.cpp\`, behind \`solve::Integrator::run_batch\`): each train folded once into one piecewise cubic of the head position
(the per-element influence cubics re-expanded on all axles' merged breakpoints: exact,
speed-independent), four speeds advanced in SIMD lanes, the loads along each piece by forward
differences, the three modal equations exactly, only the running maxima kept; the same
envelope as the general path to 1e-9. Before this kernel (commit f0dc791, the same command on
this machine on 2026-12-01, one run each): 1.28 s on 2 threads, 2.43 s on 1. Likewise the
batched Newmark of the studies above: the Old Guadiana reference variant at 60 speeds took
7.9–8.3 s on 2 threads before it and 1.6–1.9 s after (\`--set sweep.mode='"reference"'\`, two runs
each, same session). Figures of earlier dates in the project's history were measured on another
processor (AMD EPYC): compare within one page only. Envelope error against the same model at 20 kHz: $(pct "$hm_ea") (acceleration),
$(pct "$hm_ed") (deflection) — target 0.1 %. Against the full model (Newmark, 0.25 ms, with the
scenario's 45 Hz low-pass; $(fmt "$hf_wall") s on 2 threads) the three unfiltered modes differ by $(pct "$hf_ea")
and $(pct "$hf_ed"): truncation and filter together — the low-pass edge sits on the third mode (45 Hz)
and attenuates it in the reference; not the time step.

**Old Guadiana sensitivity study, all 13 models × 60 speeds, full track model** (reference:
Newmark at 0.1 ms, $(fmt "$og_ref_wall") s on 2 threads; target: ≤ 10 s with ≤ 1 % error):

| method | 2-thread wall [s] | acceleration envelope error | deflection envelope error |
|---|---|---|---|
$og_rows
Presets from \`analysis.preset\`: \`fast\` keeps the modes up to 1.5 f_c = 90 Hz, \`default\` up to
2 f_c = 120 Hz, each with one block of damping vectors (complex modes: the track's dashpots couple
them; docs/accuracy.md), static correction on, dt = 1/(16 f_c) = 1.04 ms. A filtered modal sweep
runs the same kernel as the HSLM one, with complex coordinates (split real arithmetic, four speeds
in lanes) and the station accelerations recorded for the filter (\`filtfilt_from_rest\`, maximum
between samples); the same envelope as the general path to 1e-9. Before that kernel (same day,
same machine): \`fast\` took 8.9–10.8 s, 120 Hz 16.1 s. Simulated accelerations are filtered as
responses at rest outside the record (docs/accuracy.md); with the former odd extension, whose span
in time changes with dt, the Newmark rows did not converge (0.5 ms: 3.55 %, worse than 1 ms).

**Cost of one case against model size** (Old Guadiana reference model at 288 km/h, 20 × 210 kN;
\`viaduct run ... --set track.approach_length=L --set track.exit_length=L --set track.rail_elements_per_bay=E\`;
integration only, and for the modal method the preparation — eigenproblems and tables — apart):

| approach and exit track | rail elements per bay | DOFs | Newmark [s] | modal 180 Hz [s] | modes | modal: eigenproblems, tables, filtering, output [s] |
|---|---|---|---|---|---|---|
$dof_rows
**Cost of one case against train length** (same model, regular trains of N axles 18 m apart;
integration only):

| axles | Newmark [s] | modal 180 Hz [s] |
|---|---|---|
$train_rows
**Ten trains on the track model: unit-response superposition** (HSLM-A1…A10 on the Old Guadiana
model, 10 speeds, 2 threads; errors against the direct Newmark runs, acceleration / deflection):

| method | wall [s] | error |
|---|---|---|
$unit_rows
## Records and signal processing

A 10-minute, 18-channel record at 4096 Hz (2 457 600 samples a channel), one thread, built in
memory by \`build/release/viaduct_signal_bench --minutes 10 --channels 18 --fs 4096 --csv-mb 100\`
(\`tools/bench/signal_bench.cpp\`):

| stage | wall [s] |
|---|---|
| zero-phase Chebyshev I band-pass (order 3, 1–30 Hz) of all 18 channels | $(sig filter_all_channels_s) |
| Welch PSD (Hann, 8192-point segments, 50 % overlap) of all 18 channels | $(sig welch_all_channels_s) |
| amplitude spectrum (one 2 457 600-point FFT a channel) of all 18 channels | $(sig amplitude_spectrum_all_channels_s) |
| write a $(sig csv_mb) MB record CSV | $(sig write_csv_s) |
| read it back (\`io::read_record_csv\`: parse, check every cell and the time column) | $(sig read_csv_s) |
| rainflow count (ASTM three-point, streamed in blocks of 10⁵) and Miner sum of 10⁷ samples of a random strain | $(sig rainflow_1e7_samples_s) |
DOC
echo "wrote docs/benchmarks.md" >&2
