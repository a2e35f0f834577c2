#!/usr/bin/env bash
# The CLI mutation test (tests/cli/mutations.py) at length, not a test: N mutated shipped inputs
# (default 20000) through the commands that read them, on the optimised build, the mutated file
# of every failure kept in out/mutations/. Prints the figures as a row of docs/reliability.md.
# VIADUCT=path/to/viaduct uses that binary instead of building the release preset.
#   scripts/measure/mutate.sh [N] [SEED]
set -euo pipefail
cd "$(dirname "$0")/../.."
. scripts/measure/lib.sh
n=${1:-20000}
seed=${2:-7}
if [ -z "${VIADUCT:-}" ]; then
  release_build
  VIADUCT=$V
fi
fresh_dir out/mutations
python3 tests/cli/mutations.py "$VIADUCT" . --mutations "$n" --seed "$seed" --keep out/mutations --summary
