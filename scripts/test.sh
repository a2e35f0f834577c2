#!/usr/bin/env bash
# Installs what is missing, builds and runs every test.
#   1. preset "ci": optimised, warnings as errors; unit, CLI and verification tests;
#   2. preset "dev": Debug (-O1) with AddressSanitizer + UndefinedBehaviorSanitizer; all tests again
#      (bad input must give clear errors, never a crash, under the sanitizers).
# Options: --no-sanitize (skip step 2), --jobs N.
set -euo pipefail
cd "$(dirname "$0")/.."

sanitize=1
jobs=$(nproc 2>/dev/null || echo 2)
while [ $# -gt 0 ]; do
  case "$1" in
    --no-sanitize) sanitize=0 ;;
    --jobs) jobs=$2; shift ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) echo "test.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

scripts/setup.sh

run_preset() {
  local preset=$1 labels=$2
  echo "== $preset: configure and build" >&2
  cmake --preset "$preset" -G Ninja >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
  echo "== $preset: tests ($labels)" >&2
  ctest --preset "$preset" -j "$jobs" -L "$labels"
}

run_preset ci "unit|cli|verification"
if [ "$sanitize" -eq 1 ]; then
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    run_preset dev "unit|cli|verification"
fi
echo "== all tests passed" >&2
