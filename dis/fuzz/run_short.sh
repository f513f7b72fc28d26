#!/bin/sh
# Builds the DIS decoder's libFuzzer target with clang in a build tree of its own (the fuzz
# preset's settings) and fuzzes it for 50 000 runs, so every preset's test suite includes a
# short fuzzing run although its own compiler is gcc.
#   run_short.sh <source dir> <build dir>
# Exits 77 (skipped) without clang++; a build failure or a finding fails the test.
set -eu
src=$1
build=$2
if ! command -v clang++ >/dev/null 2>&1; then
  echo "clang++ not found (scripts/setup.sh installs it): skipped"
  exit 77
fi
mkdir -p "$build"
log="$build/run_short.log"
if ! (cd "$src" && cmake --preset fuzz -B "$build" && cmake --build "$build" -j 2 --target dis_decode_fuzzer) >"$log" 2>&1; then
  tail -n 40 "$log"
  echo "building dis_decode_fuzzer with clang failed (whole log: $log)"
  exit 1
fi
# New inputs go to the build tree, never into the committed seed corpus.
mkdir -p "$build/dis_fuzz_out"
exec "$build/dis/dis_decode_fuzzer" -runs=50000 -seed=1 -max_len=2000 "$build/dis_fuzz_out" \
  "$src/dis/fuzz/corpus"
