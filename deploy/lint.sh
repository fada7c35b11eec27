#!/usr/bin/env bash
# clang-tidy over the project's own sources with the checks in .clang-tidy (any warning fails), using
# the compile commands of a configured build (deploy/test.sh configures build/). KESSLER_LINT_CACHE
# (default ~/.cache/kessler-lint) keeps which files passed; remove it to check every file again.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f build/compile_commands.json ] || cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
# Generated protobuf and gRPC headers must exist before clang-tidy reads the sources that include them.
cmake --build build -j"$(nproc)" >/dev/null
mapfile -t files < <(git ls-files 'core/*.cpp' 'server/*.cpp' 'client/*.cpp')
# Each file is skipped when it passed before with the same preprocessed text (deploy/clang_tidy_cached.py).
python3 deploy/clang_tidy_cached.py build "${files[@]}"
