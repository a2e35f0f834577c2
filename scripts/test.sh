#!/usr/bin/env bash
# Installs what is missing, builds and runs every test. Both presets compile through ccache
# (installed here; CMakeLists.txt, VIADUCT_CCACHE): on a machine that has run it before, a fresh
# clone recompiles only what changed and the run takes about 10 minutes on 2 cores, the tests most
# of it; the first run on a machine, or after a change to a header every module includes, about 20
# to 25 minutes (docs/benchmarks.md, "Build and CI time").
#   1. preset "ci": optimised, warnings as errors; every test (labels unit, cli, verification, long);
#   2. preset "sanitize" (the dev preset at -g1, without the benchmark programs): AddressSanitizer +
#      UndefinedBehaviorSanitizer on every test but those labelled "long" (bad input must give
#      clear errors, never a crash, under the sanitizers). The long ones (over 5 s under the
#      sanitizers, up to minutes) repeat on larger models the code paths that the shorter unit,
#      verification and CLI tests take under the sanitizers, and run in step 1; so do the CLI
#      tests that check results, outputs and sample runs (the bad- and extreme-input ones, the
#      mutation and fuzz tests run under the sanitizers).
# Options: --no-sanitize (skip step 2), --jobs N.
set -euo pipefail
cd "$(dirname "$0")/.."

sanitize=1
jobs=$(nproc 2>/dev/null || echo 2)
while [ $# -gt 0 ]; do
  case "$1" in
    --no-sanitize) sanitize=0 ;;
    --jobs) jobs=$2; shift ;;
    -h|--help) sed -n '2,/^# Options/p' "$0"; exit 0 ;;
    *) echo "test.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

scripts/setup.sh --tests

run_preset() {
  local preset=$1
  shift
  echo "== $preset: configure and build (${SECONDS} s in)" >&2
  cmake --preset "$preset" -G Ninja >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
  echo "== $preset: tests ($*) (${SECONDS} s in)" >&2
  ctest --preset "$preset" -j "$jobs" "$@"
}

run_preset ci -L "unit|cli|verification|long"
if [ "$sanitize" -eq 1 ]; then
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    run_preset sanitize -L "unit|cli|verification" -LE long
fi
echo "== all tests passed (${SECONDS} s)" >&2
