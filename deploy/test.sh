#!/usr/bin/env bash
# The README's test command: configure, build (Release), run every GoogleTest through ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
# Test suites run side by side: OpenMP threads that spin at barriers would starve each other.
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
# With MPI: kessler-mpi and its tests (tests/mpi/, under mpirun; OpenMPI from install-deps.sh).
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DKESSLER_MPI=ON >/dev/null
cmake --build build -j"$jobs"
ctest --test-dir build --output-on-failure -j"$jobs" --timeout 900
