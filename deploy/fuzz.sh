#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz/, clang-14, ASan and UBSan) in build-sanitize and runs each for
# SECONDS (default 5) from its seed corpus; a crash stops the script with the harness's report and the
# input in build-sanitize/findings/. Usage: deploy/fuzz.sh [SECONDS] [HARNESS...]
#   deploy/fuzz.sh 5                    # CI: a few seconds each
#   deploy/fuzz.sh 3600 fuzz_scenario   # a long run of one harness
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-5}
shift || true
jobs=$(nproc)
source deploy/sanitized-build.sh
configure_sanitized_build
harnesses=("$@")
if [ ${#harnesses[@]} -eq 0 ]; then
  for f in tests/fuzz/harnesses/fuzz_*.cpp; do harnesses+=("$(basename "$f" .cpp)"); done
fi
cmake --build build-sanitize -j"$jobs" --target "${harnesses[@]}"
mkdir -p build-sanitize/findings
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
for h in "${harnesses[@]}"; do
  name=${h#fuzz_}
  work=build-sanitize/corpus/$name
  mkdir -p "$work"
  # New inputs go to the work folder; the checked-in seeds stay as they are.
  log=build-sanitize/findings/$h.log
  if ! build-sanitize/bin/"$h" -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=65536 -timeout=10 \
      -artifact_prefix=build-sanitize/findings/"$h"- -print_final_stats=1 \
      "$work" tests/fuzz/corpus/"$name" >"$log" 2>&1; then
    tail -50 "$log"
    echo "fuzz: $h failed; the input is in build-sanitize/findings/ (add it to tests/fuzz/regressions/$name/)" >&2
    exit 1
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  echo "fuzz: $h clean, $runs executions in ${seconds} s"
done
