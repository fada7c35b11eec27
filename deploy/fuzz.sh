#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz/, clang-14, ASan and UBSan) in build-fuzz and runs each for
# SECONDS (default 5) from its seed corpus; a crash stops the script with the harness's report and the
# input in build-fuzz/findings/. Usage: deploy/fuzz.sh [SECONDS] [HARNESS...]
#   deploy/fuzz.sh 5                    # CI: a few seconds each
#   deploy/fuzz.sh 3600 fuzz_scenario   # a long run of one harness
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-5}
shift || true
jobs=$(nproc)
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS=-O1 -DKESSLER_FUZZ=ON \
  -DCMAKE_CXX_COMPILER=clang++-14 -DKESSLER_NATIVE=OFF ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER} >/dev/null
cmake --build build-fuzz -j"$jobs"
harnesses=("$@")
if [ ${#harnesses[@]} -eq 0 ]; then
  for f in tests/fuzz/harnesses/fuzz_*.cpp; do harnesses+=("$(basename "$f" .cpp)"); done
fi
mkdir -p build-fuzz/findings
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
for h in "${harnesses[@]}"; do
  name=${h#fuzz_}
  work=build-fuzz/corpus/$name
  mkdir -p "$work"
  # New inputs go to the work folder; the checked-in seeds stay as they are.
  log=build-fuzz/findings/$h.log
  if ! build-fuzz/bin/"$h" -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=65536 -timeout=10 \
      -artifact_prefix=build-fuzz/findings/"$h"- -print_final_stats=1 \
      "$work" tests/fuzz/corpus/"$name" >"$log" 2>&1; then
    tail -50 "$log"
    echo "fuzz: $h failed; the input is in build-fuzz/findings/ (add it to tests/fuzz/regressions/$name/)" >&2
    exit 1
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  echo "fuzz: $h clean, $runs executions in ${seconds} s"
done
