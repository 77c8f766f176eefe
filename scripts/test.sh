#!/usr/bin/env bash
# Build uniarc with the Debug checks (bounds, FPE traps) and run the whole test suite through CTest;
# then build it optimised (Release, as users run it) and run the unit tests there too: a fault that
# only optimised code shows (an uninitialised status read as a refusal) passed the Debug suite once;
# and one path test whose branch round-off used to choose.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-tests -DCMAKE_BUILD_TYPE=Debug >/dev/null
cmake --build build-tests -j"$(nproc)"
ctest --test-dir build-tests --output-on-failure -j"$(nproc)"
cmake -S . -B build-release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build-release -j"$(nproc)"
ctest --test-dir build-release --output-on-failure -j"$(nproc)" -L unit
# A path whose branch round-off could choose (docs/testing.md): the Release build must trace the same
# symmetric path as the Debug suite (about a second).
ctest --test-dir build-release --output-on-failure -R '^path_corner_pipeline_hump_200$'
