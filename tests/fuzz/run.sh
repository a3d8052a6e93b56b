#!/usr/bin/env bash
# Builds libFuzzer targets (tests/fuzz/fuzz_NAME.cpp) with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer, and runs each for a bounded time over its seed corpus
# (tests/fuzz/corpus/NAME/, whose files are replayed first: a crash once found and added there is a
# regression test from then on).
#   usage: run.sh SOURCE_DIR WORK_DIR SECONDS NAME...
# Each target names the project sources it needs on a "// SOURCES:" line and libraries on "// LIBS:".
# Exit status: 0 clean; 1 a target crashed or failed to build (the reproducer is in WORK_DIR/crashes/);
# 2 usage; 77 clang++ is missing (the test is then reported as skipped, with the reason).
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: run.sh SOURCE_DIR WORK_DIR SECONDS NAME..." >&2; exit 2; }
src=$1 work=$2 seconds=$3
shift 3
cxx=$(command -v clang++ || command -v clang++-14 || true)
if [ -z "$cxx" ]; then
  echo "SKIP: clang++ is not installed (Debian package clang), so the libFuzzer targets cannot be built" >&2
  exit 77
fi
mkdir -p "$work/crashes"
for name in "$@"; do
  file="$src/tests/fuzz/fuzz_$name.cpp"
  [ -f "$file" ] || { echo "no fuzz target $file" >&2; exit 2; }
  sources=$(sed -n 's|^// SOURCES:||p' "$file")
  libs=$(sed -n 's|^// LIBS:||p' "$file")
  paths=()
  for s in $sources; do paths+=("$src/$s"); done
  echo "== fuzz_$name: building with $cxx"
  "$cxx" -std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -I "$src" \
    "$file" "${paths[@]}" $libs -o "$work/fuzz_$name"
  mkdir -p "$work/corpus-$name"
  echo "== fuzz_$name: $seconds s over tests/fuzz/corpus/$name"
  # The first corpus folder receives what the run discovers; the committed seeds stay as they are.
  if ! "$work/fuzz_$name" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -artifact_prefix="$work/crashes/$name-" "$work/corpus-$name" "$src/tests/fuzz/corpus/$name" 2>"$work/fuzz_$name.log"; then
    tail -n 60 "$work/fuzz_$name.log" >&2
    echo "FAIL: fuzz_$name found a crash; the input is in $work/crashes/ (add it to tests/fuzz/corpus/$name/ once fixed)" >&2
    exit 1
  fi
  grep -E "stat::number_of_executed_units|Done [0-9]+ runs" "$work/fuzz_$name.log" | tail -n 2
done
echo "fuzz: all targets clean"
