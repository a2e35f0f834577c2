#!/usr/bin/env bash
# Every subcommand's --help works, and every sample run it shows succeeds.
. "$(dirname "$0")/lib.sh"
ln -s "$SRC/scenarios" "$WORK/scenarios"
ln -s "$SRC/data" "$WORK/data"
cd "$WORK" || exit 1
expect 0 "Commands:" -- "$VIADUCT" --help
for cmd in check modes run sweep schema filter spectrum peaks compare speed resample envelope frf shaker modal-fit decay fit; do
  expect 0 "Sample runs:" -- "$VIADUCT" "$cmd" --help
  while IFS= read -r line; do
    # shellcheck disable=SC2086
    eval "set -- ${line#  viaduct }"
    expect 0 "" -- "$VIADUCT" "$@" --quiet
  done < <("$VIADUCT" "$cmd" --help | grep '^  viaduct ')
done
finish
