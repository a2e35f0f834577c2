# Helpers for the CLI tests: VIADUCT (binary), SRC (source dir), WORK (scratch dir, removed at exit).
set -u
VIADUCT=$1
SRC=$2
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
n_fail=0
n_pass=0

# expect CODE PATTERN -- command...: runs the command, checks exit code and that stderr+stdout
# contains PATTERN (grep -F).
expect() {
  local code=$1 pattern=$2
  shift 3
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  if [ "$rc" != "$code" ] || ! grep -qF -- "$pattern" <<<"$out"; then
    echo "FAIL: $* -> exit $rc (want $code), output:"
    echo "$out" | head -20
    echo "(wanted to see: $pattern)"
    n_fail=$((n_fail + 1))
  else
    n_pass=$((n_pass + 1))
  fi
}

# same DIR_A DIR_B FILE...: every file byte for byte.
same() {
  local a=$1 b=$2 f
  shift 2
  for f in "$@"; do expect 0 "" -- cmp "$a/$f" "$b/$f"; done
}

# Writes scenario file $1: a 15 m span without track (EI 7.694e9 N·m², 15 t/m, 1.35 % damping),
# trains $2 (TOML list items), dt 2 ms and a mid-span station; the caller appends the rest.
light_span() {
  cat > "$1" <<EOF
[bridge]
span_lengths = [15.0]
EI = 7.694e9
mass_per_m = 15000.0
[bridge.damping]
ratio = 0.0135
[train]
files = [$2]
[analysis]
dt = 0.002
[[stations]]
name = "mid"
span = 1
at = 0.5
EOF
}

finish() {
  echo "$n_pass passed, $n_fail failed"
  [ "$n_fail" -eq 0 ]
}
