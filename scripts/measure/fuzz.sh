#!/usr/bin/env bash
# Coverage-guided fuzzing of the parsers with libFuzzer (issue #18), not a test: builds the fuzz
# preset (clang, ASan/UBSan), runs every harness of tests/fuzz for RUNS executions (default 10⁶)
# from a copy of the committed corpus, and writes the figures (executions, time, coverage,
# findings) into docs/reliability.md between its fuzzing markers. A finding stops its harness and
# leaves the reproducer in out/fuzz/TARGET/ (crash-*, leak-*, timeout-*); add it to
# tests/fuzz/corpus/TARGET once fixed, so that CI replays it.
#   scripts/measure/fuzz.sh [RUNS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/measure/lib.sh
runs=${1:-1000000}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scenario train record uff frf)
scripts/setup.sh
if ! command -v clang++ >/dev/null || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  apt-get install -y --no-install-recommends clang libclang-rt-dev >/dev/null 2>&1 ||
    apt-get install -y --no-install-recommends clang-14 libclang-rt-14-dev >/dev/null
fi
cmake --preset fuzz -G Ninja >/dev/null
cmake --build --preset fuzz -j "$(nproc)" >/dev/null
O=out/fuzz
mkdir -p "$O"
rows=()
status=0
for t in "${targets[@]}"; do
  fresh_dir "$O/$t"
  cp -r "tests/fuzz/corpus/$t" "$O/$t/corpus"
  log="$O/$t/fuzz.log"
  start=$(date +%s)
  set +e
  (cd "$O/$t" && ASAN_OPTIONS=detect_leaks=1 "../../../build/fuzz/tests/fuzz/viaduct_fuzz_$t" corpus \
     -runs="$runs" -max_len=65536 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 > fuzz.log 2>&1)
  rc=$?
  set -e
  secs=$(( $(date +%s) - start ))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  corpus=$(ls "$O/$t/corpus" | wc -l)
  findings=$(ls "$O/$t" | grep -cE '^(crash|leak|timeout|oom)-' || true)
  [ "$rc" -eq 0 ] || status=1
  echo "$t: ${execs:-?} executions in $secs s, coverage $cov edges / $ft features, corpus $corpus, findings $findings (exit $rc)" >&2
  rows+=("| $t | ${execs:-?} | $secs | ${cov:-?} | ${ft:-?} | $corpus | $findings |")
done
python3 - "$runs" "${rows[@]}" <<'PY'
# The rows of the harnesses run now replace theirs (dated); the others' stay.
import re, sys, subprocess, datetime
runs, new = sys.argv[1], sys.argv[2:]
p = "docs/reliability.md"
s = open(p).read()
m = re.search(r"<!-- fuzz: written by scripts/measure/fuzz.sh -->.*?<!-- /fuzz -->", s, flags=re.S)
old = {}
for line in (m.group(0).splitlines() if m else []):
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    if line.startswith("| ") and len(cells) == 8 and cells[0] not in ("harness",):
        old[cells[0]] = line
today, cores = datetime.date.today(), subprocess.check_output(["nproc"]).decode().strip()
for row in new:
    name = row.strip("| ").split(" |")[0]
    old[name] = row.rstrip(" |") + f" | {today} |"
header = "| harness | executions | seconds | coverage (edges) | features | corpus after | findings | date |\n|---|---|---|---|---|---|---|---|"
order = ["scenario", "train", "record", "uff", "frf"]
table = "\n".join([header] + [old[k] for k in order if k in old])
block = (f"<!-- fuzz: written by scripts/measure/fuzz.sh -->\n"
         f"Measured by `scripts/measure/fuzz.sh RUNS` ({cores} cores): libFuzzer (clang, ASan/UBSan, leak detection) "
         f"from the committed corpus, RUNS executions per harness (10⁶ here), inputs up to 64 kB, 10 s per input, 2 GB.\n\n"
         f"{table}\n<!-- /fuzz -->")
s = s[:m.start()] + block + s[m.end():] if m else s + "\n" + block + "\n"
open(p, "w").write(s)
PY
echo "wrote docs/reliability.md" >&2
exit $status
