#!/usr/bin/env bash
# Sourced by deploy/sanitize.sh and deploy/fuzz.sh: configures build-sanitize, the one ASan + UBSan build
# (clang-14, -O1, assertions on, coverage instrumentation for libFuzzer) whose compile the whole test suite
# and the fuzz harnesses share (the bench is left out of it).
configure_sanitized_build() {
  cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS=-O1 \
    -DCMAKE_CXX_COMPILER=clang++-14 -DKESSLER_SANITIZE=ON -DKESSLER_FUZZ=ON -DKESSLER_NATIVE=OFF -DKESSLER_MPI=ON \
    ${CMAKE_CXX_COMPILER_LAUNCHER:+-DCMAKE_CXX_COMPILER_LAUNCHER=$CMAKE_CXX_COMPILER_LAUNCHER} >/dev/null
}
