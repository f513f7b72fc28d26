#!/bin/sh
# Builds one libFuzzer target with clang in a build tree of its own (the fuzz preset's settings)
# and fuzzes it for a bounded number of runs, so every preset's test suite includes a short
# fuzzing run although its own compiler is gcc. The pdu and dis short runs share one tree (their
# ctest entries hold one resource lock), so the second builds only what the first did not.
#   fuzz_short.sh <source dir> <build dir> <target> <target's folder> <runs> <max_len>
# The seed corpus is <source dir>/<target's folder>/fuzz/corpus.
# Exits 77 (skipped) without clang++; a build failure or a finding fails the test.
set -eu
src=$1
build=$2
target=$3
folder=$4
runs=$5
max_len=$6
if ! command -v clang++ >/dev/null 2>&1; then
  echo "clang++ not found (scripts/setup.sh installs it): skipped"
  exit 77
fi
mkdir -p "$build"
log="$build/$target.log"
if ! (cd "$src" && cmake --preset fuzz -B "$build" && cmake --build "$build" -j 2 --target "$target") >"$log" 2>&1; then
  tail -n 40 "$log"
  echo "building $target with clang failed (whole log: $log)"
  exit 1
fi
# New inputs go to the build tree, never into the committed seed corpus.
mkdir -p "$build/${target}_out"
exec "$build/$folder/$target" -runs="$runs" -seed=1 -max_len="$max_len" "$build/${target}_out" \
  "$src/$folder/fuzz/corpus"
