# Shared by the measuring scripts (source it after cd to the repository root).

# Installs the packages and builds the release preset quietly; V is its viaduct.
release_build() {
  scripts/setup.sh
  cmake --preset release -G Ninja >/dev/null
  cmake --build --preset release -j "$(nproc)" >/dev/null
  V=build/release/viaduct
}

# An empty output directory.
fresh_dir() {
  rm -rf "$1"
  mkdir -p "$1"
}

# The median of the numbers on stdin, one per line.
median() { sort -g | awk '{a[NR]=$1} END{print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }

# A benchmark's start: `repeats` from --repeats N (default 3), the release build, a fresh
# output directory B.   bench_start DIR "$@"
bench_start() {
  B=$1
  shift
  repeats=3
  if [ "${1:-}" = "--repeats" ]; then repeats=$2; fi
  release_build
  fresh_dir "$B"
}
