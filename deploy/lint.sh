#!/usr/bin/env bash
# clang-tidy over the project's own sources with the checks in .clang-tidy (any warning fails). It reads
# each file on its own, so it uses a build folder of its own, build-lint: configured without batches or
# precompiled headers, only the generated protobuf and gRPC sources built. A file that passed before with
# the same preprocessed text is skipped (deploy/clang_tidy_cached.py: the local cache KESSLER_LINT_CACHE,
# default ~/.cache/kessler-lint, and the tree's deploy/lint-passed.txt, which a clean run updates: commit it).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-lint -G Ninja -DCMAKE_BUILD_TYPE=Release -DKESSLER_MPI=ON -DKESSLER_UNITY_BUILD=OFF \
  -DKESSLER_PRECOMPILE_HEADERS=OFF >/dev/null
cmake --build build-lint --target kessler_generated_sources >/dev/null
mapfile -t files < <(git ls-files 'core/*.cpp' 'server/*.cpp' 'client/*.cpp')
python3 deploy/clang_tidy_cached.py build-lint "${files[@]}"
