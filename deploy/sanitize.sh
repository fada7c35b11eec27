#!/usr/bin/env bash
# The whole test suite (with MPI) built with AddressSanitizer and UndefinedBehaviorSanitizer
# (-DKESSLER_SANITIZE=ON) in build-sanitize, run through ctest; CI runs it after the README's test command.
# Leak checking is off here; the fuzz harnesses check for leaks (deploy/fuzz.sh).
# Usage: deploy/sanitize.sh [CTEST ARGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DKESSLER_SANITIZE=ON -DKESSLER_NATIVE=OFF -DKESSLER_MPI=ON \
  ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER} >/dev/null
cmake --build build-sanitize -j"$jobs"
ctest --test-dir build-sanitize --output-on-failure -j"$jobs" --timeout 3600 "$@"
