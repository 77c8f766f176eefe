#!/usr/bin/env bash
# Build uniarc with the Debug checks (bounds, FPE traps) and run the whole test suite through CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-tests -DCMAKE_BUILD_TYPE=Debug >/dev/null
cmake --build build-tests -j"$(nproc)"
ctest --test-dir build-tests --output-on-failure -j"$(nproc)"
