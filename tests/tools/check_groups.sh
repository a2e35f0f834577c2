#!/usr/bin/env bash
# The sanitize preset runs a Catch test binary as one process per source file (tests/CMakeLists.txt):
# check that those groups, together, hold every test case the binary has outside [long]. Catch gives
# each case one file-name tag (-#), so the groups hold every case once when every file tag of the
# cases outside [long] is among the groups' (one listing: a process costs 0.24 s under the sanitizers).
#   check_groups.sh BINARY FILE_TAG...      (FILE_TAG: a source file's name without its extension)
set -euo pipefail
bin=$1
shift
# Catch2 v2's listings exit with the number of items listed: their status says nothing.
listed=$({ "$bin" -# --list-tags "~[long]" || true; } | sed -n 's/.*\[#\([^]]*\)\].*/\1/p' | sort -u)
[ -n "$listed" ] || { echo "FAIL: $bin lists no test case outside [long]"; exit 1; }
missing=$(comm -23 <(echo "$listed") <(printf '%s\n' "$@" | sort -u))
if [ -n "$missing" ]; then
  echo "FAIL: cases of $bin in files that no group runs: $missing"
  exit 1
fi
echo "ok: the cases of $(echo "$listed" | wc -l) files in $# per-file groups"
