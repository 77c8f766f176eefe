#!/usr/bin/env bash
# Build uniarc with the Debug checks (bounds, FPE traps) and run the whole test suite through CTest;
# then build it optimised (Release, as users run it) and run the unit tests there too: a fault that
# only optimised code shows (an uninitialised status read as a refusal) passed the Debug suite once.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-tests -DCMAKE_BUILD_TYPE=Debug >/dev/null
cmake --build build-tests -j"$(nproc)"
ctest --test-dir build-tests --output-on-failure -j"$(nproc)"
cmake -S . -B build-release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build-release -j"$(nproc)"
ctest --test-dir build-release --output-on-failure -j"$(nproc)" -L unit
