#!/usr/bin/env bash
# Benchmark of `viaduct assess` (issue #20): wall time of the Old Guadiana assessment with its
# track (HSLM-A1...A10 and the Talgo, speeds to 1.2 x 300 km/h refined around every resonance, two
# mass bounds) and its accuracy on the governing peaks against a converged Newmark reference:
# each governing case (the deck accelerations' and the mid-span moments' worst train, speed and
# mass case) run again alone with `viaduct run`, Newmark at 0.2 and 0.1 ms, the same model,
# damping and filter (mass_cases.csv). Writes docs/benchmarks-assess.md.
#   scripts/measure/bench_assess.sh [--repeats N]
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/measure/lib.sh
repeats=3
while [ $# -gt 0 ]; do
  case "$1" in
    --repeats) repeats=$2; shift ;;
    *) echo "bench_assess.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
release_build
B=out/bench-assess
fresh_dir "$B"
S=scenarios/old-guadiana-assess.toml
now() { date +%s.%N; }
walls=()
for i in $(seq "$repeats"); do
  t0=$(now)
  "$V" assess "$S" --threads 2 --quiet --no-plots --out "$B/t2-$i"
  walls+=("$(echo "$(now) - $t0" | bc)")
done
w2=$(printf '%s\n' "${walls[@]}" | median)
t0=$(now)
"$V" assess "$S" --threads 1 --quiet --no-plots --out "$B/t1"
w1=$(echo "$(now) - $t0" | bc)
t0=$(now)
/usr/bin/python3 scripts/plot/plot_assess.py "$B/t2-1" >/dev/null
wp=$(echo "$(now) - $t0" | bc)
n_cases=$(sed -n 's/^n_cases = //p' "$B/t2-1/manifest.toml" | tr -d '"')
echo "bench_assess: $n_cases cases, 2 threads median ${w2} s, 1 thread ${w1} s, figures ${wp} s" >&2

# The cheaper readings a user may choose (each an accuracy choice; the scenario keeps "default"):
# one run each on 2 threads, without figures or PDF; their governing values are compared below.
options=("damping_vectors=0:--set modal.damping_vectors=0"
         "fast:--set analysis.preset=\"fast\""
         "fast, damping_vectors=0:--set analysis.preset=\"fast\" --set modal.damping_vectors=0")
opt_walls=()
for k in "${!options[@]}"; do
  read -r -a args <<<"${options[$k]#*:}"
  t0=$(now)
  "$V" assess "$S" --threads 2 --quiet --no-plots --no-pdf "${args[@]}" --out "$B/opt-$k"
  opt_walls+=("$(echo "$(now) - $t0" | bc)")
done
t0=$(now)
"$V" assess "$S" --threads 2 --quiet --no-plots --no-pdf --out "$B/opt-default"
w_default=$(echo "$(now) - $t0" | bc)

# Accuracy of the governing peaks against Newmark runs of the same cases.
opt_names=$(printf '%s\n' "${options[@]}" | sed 's/:.*//' | paste -sd'|')
rows=$(/usr/bin/python3 - "$V" "$S" "$B" "$opt_names" "${#options[@]}" <<'PY'
import csv, subprocess, sys
V, S, B = sys.argv[1:4]
opt_names, n_opt = sys.argv[4].split("|"), int(sys.argv[5])
A = B + "/t2-1"
checks = list(csv.DictReader(open(A + "/checks.csv")))
mass = {r["variant"]: r for r in csv.DictReader(open(A + "/mass_cases.csv")) if r["span"] == "1"}
effects = list(csv.DictReader(open(A + "/load_effects.csv")))
env = list(csv.DictReader(open(A + "/envelope.csv")))

def peak_between_samples(y):
    # the largest |y| with the parabola through the largest sample and its neighbours (as viaduct does)
    i = max(range(len(y)), key=lambda k: abs(y[k]))
    if 0 < i < len(y) - 1:
        a, b, c = y[i - 1], y[i], y[i + 1]
        d = a - 2 * b + c
        if d != 0:
            u = 0.5 * (a - c) / d
            if abs(u) <= 1:
                return abs(b - 0.25 * (a - c) * u)
    return abs(y[i])

def rerun(train, speed, variant, dt, out):
    m = mass[variant]
    num = train.split("-A")[-1]
    files = '["hslm:A%s"]' % num if train.startswith("HSLM-A") else None
    cmd = [V, "run", S, "--quiet", "--out", out, "--speed-kmh", speed, "--train", train,
           "--set", "bridge.mass_per_m=%s" % m["mass_per_m_kgpm"], "--set", 'bridge.damping.kind="modal"',
           "--set", "bridge.damping.ratio=%s" % m["damping_ratio"], "--set", 'filter.band="lowpass"',
           "--set", "filter.high_hz=%s" % m["cutoff_hz"], "--set", 'analysis.method="newmark"',
           "--set", "analysis.dt=%g" % dt]
    if files:
        cmd += ["--set", "train.files=" + files]
    subprocess.run(cmd, check=True)
    return list(csv.DictReader(open(out + "/history.csv")))

cases = [(r["quantity"], r["train"], r["speed_kmh"], r["variant"], float(r["value"]))
         for r in checks if r["check"] == "deck acceleration"]
for r in checks:  # the mid-span moments' governing dynamic case: the largest |M| over the cases
    if r["check"] == "dynamic design effect vs LM71" and r["quantity"].endswith("_moment_Nm"):
        q = r["quantity"]
        best = max((e for e in effects if e["quantity"] == q), key=lambda e: float(e["max_abs"]))
        cases.append((q, best["train"], best["speed_kmh"], best["variant"], float(best["max_abs"])))
def option_value(d, q, train, speed, variant):
    # the same case's value in an option's results (the same model: the same speeds)
    if q.endswith("_acc_mps2"):
        for r in csv.DictReader(open(d + "/envelope.csv")):
            if (r["station"] + "_acc_mps2", r["train"], r["speed_kmh"], r["variant"]) == (q, train, speed, variant):
                return float(r["max_abs_acc_mps2"])
    else:
        for r in csv.DictReader(open(d + "/load_effects.csv")):
            if (r["quantity"], r["train"], r["speed_kmh"], r["variant"]) == (q, train, speed, variant):
                return float(r["max_abs"])
    return float("nan")

opt_err, def_err = [[] for _ in range(n_opt)], []
for k, (q, train, speed, variant, value) in enumerate(cases):
    refs = []
    for dt in (2e-4, 1e-4):
        h = rerun(train, speed, variant, dt, "%s/ref-%d-%g" % (B, k, dt))
        col = q.replace("_acc_mps2", "_acc_filt_mps2")
        y = [float(x[col]) for x in h]
        refs.append(peak_between_samples(y) if q.endswith("_acc_mps2") else max(abs(v) for v in y))
    err = value / refs[1] - 1
    conv = refs[0] / refs[1] - 1
    print("| %s | %s | %.2f | %s | %.5g | %.5g | %+.3f %% | %+.3f %% |" % (q, train, float(speed), variant, value, refs[1], 100 * err, 100 * conv))
    def_err.append(err)
    for o in range(n_opt):
        opt_err[o].append(option_value("%s/opt-%d" % (B, o), q, train, speed, variant) / refs[1] - 1)
# the options' errors on the same cases, after a marker line the shell splits on
print("OPTIONS")
for o in range(n_opt):
    e = opt_err[o]
    print("%s|%+.3f %%|%+.3f %%|%.3f %%" % (opt_names[o], 100 * min(e), 100 * max(e), 100 * max(abs(x) for x in e)))
print("default|%+.3f %%|%+.3f %%|%.3f %%" % (100 * min(def_err), 100 * max(def_err), 100 * max(abs(x) for x in def_err)))
PY
)
opt_rows=$(printf '%s\n' "$rows" | sed -n '/^OPTIONS$/,$p' | sed 1d)
rows=$(printf '%s\n' "$rows" | sed '/^OPTIONS$/,$d')
option_table=""
while IFS='|' read -r name lo hi worst; do
  if [ "$name" = default ]; then wall=$w_default; args="(as shipped)"; else
    for k in "${!options[@]}"; do [ "${options[$k]%%:*}" = "$name" ] && wall=${opt_walls[$k]} && args="\`${options[$k]#*:}\`"; done
  fi
  option_table+="| $name | $args | $(printf '%.1f' "$wall") | $lo to $hi | $worst |"$'\n'
done <<<"$opt_rows"
cat > docs/benchmarks-assess.md <<MD
# Benchmark: the EN 1991-2 assessment (\`viaduct assess\`)

Measured by \`scripts/measure/bench_assess.sh\` on $(date +%Y-%m-%d), 2 cores ($(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1)),
release preset. The machine is shared and noisy: the 2-thread time is the median of $repeats runs,
the 1-thread time one run. Speed is measured here, never asserted in tests.

## Wall time

| study | cases | 1 thread [s] | 2 threads [s] | target |
|---|---|---|---|---|
| Old Guadiana with its track (\`$S\`): HSLM-A1…A10 and the Talgo, $(sed -n 's/^line_speed_kmh = //p' "$B/t2-1/manifest.toml" | tr -d '"') km/h line, speeds to 1.2 × it refined around every resonance, two mass bounds | $n_cases | $(printf '%.1f' "$w1") | $(printf '%.1f' "$w2") | ≤ 15 s on 2 cores |

Command: \`build/release/viaduct assess $S --threads N --no-plots\` (the whole command: scenario,
modes, damping and cut-off, the sweep with load effects through the modal peaks kernel, LM71 and
the trains' static effects from influence lines, the checks, the tables, report.md, report.html
and report.pdf). The
figures (\`scripts/plot/plot_assess.py\`, run by \`viaduct assess\` without \`--no-plots\`) take
$(printf '%.1f' "$wp") s more.

## Accuracy of the governing peaks

Each governing case run again alone with \`viaduct run\`: Newmark (average acceleration) at
0.1 ms, the same model, mass case, damping and low-pass at the cut-off (\`mass_cases.csv\`). The
assessment runs modal superposition (\`analysis.preset = "default"\`: modes to the cut-off's
preset, its time step). "Newmark 0.2 vs 0.1 ms" shows how converged the reference is.

| quantity | train | speed [km/h] | mass case | assess | Newmark 0.1 ms | assess error | Newmark 0.2 vs 0.1 ms |
|---|---|---|---|---|---|---|---|
$rows

## Cheaper readings, and what they cost in accuracy

The same assessment with a smaller modal basis (one run each, 2 threads, \`--no-plots --no-pdf\`:
the computation, the tables and report.md), and each one's values for the governing cases above
against the same Newmark runs at 0.1 ms. Which to take is an accuracy choice for whoever signs
the assessment; the scenario keeps \`default\`.

| reading | keys | 2 threads [s] | errors on the governing cases | largest |
|---|---|---|---|---|
$option_table
MD
echo "bench_assess: wrote docs/benchmarks-assess.md" >&2
