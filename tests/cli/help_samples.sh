#!/usr/bin/env bash
# Every subcommand's --help works, and every sample run it shows succeeds.
# Usage: help_samples.sh VIADUCT SRC [COMMAND...]   (default: every subcommand; CMake registers one
# test per subcommand so that each stays short and they run in parallel)
. "$(dirname "$0")/lib.sh"
ln -s "$SRC/scenarios" "$WORK/scenarios"
ln -s "$SRC/data" "$WORK/data"
cd "$WORK" || exit 1
expect 0 "Commands:" -- "$VIADUCT" --help
commands=("${@:3}")
[ ${#commands[@]} -gt 0 ] || commands=(check modes run sweep schema filter spectrum peaks compare speed resample envelope frf
                                       shaker modal-fit decay fit)
for cmd in "${commands[@]}"; do
  expect 0 "Sample runs:" -- "$VIADUCT" "$cmd" --help
  while IFS= read -r line; do
    # shellcheck disable=SC2086
    eval "set -- ${line#  viaduct }"
    expect 0 "" -- "$VIADUCT" "$@" --quiet
  done < <("$VIADUCT" "$cmd" --help | grep '^  viaduct ')
done
finish
