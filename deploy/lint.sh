#!/usr/bin/env bash
# clang-tidy over the project's own sources with the checks in .clang-tidy (any warning fails), using
# the compile commands of a configured build (deploy/test.sh configures build/).
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f build/compile_commands.json ] || cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
# Generated protobuf and gRPC headers must exist before clang-tidy reads the sources that include them.
cmake --build build -j"$(nproc)" >/dev/null
mapfile -t files < <(git ls-files 'core/*.cpp' 'server/*.cpp' 'client/*.cpp')
run-clang-tidy -p build -j "$(nproc)" -quiet "${files[@]}" >build/clang-tidy.log 2>&1 || {
  grep -E 'warning:|error:' build/clang-tidy.log | sed 's/\x1b\[[0-9;]*m//g' | sort -u >&2
  echo "lint: clang-tidy found problems (full log: build/clang-tidy.log)" >&2
  exit 1
}
echo "lint: clang-tidy clean on ${#files[@]} files"
