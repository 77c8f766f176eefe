#!/usr/bin/env bash
# The main job in one command: install what is missing, build uniarc (Release), and run an example deck
# end to end. Usage: bash scripts/quickstart.sh [DECK]   (default: input/walker_arch.inp)
set -euo pipefail
cd "$(dirname "$0")/.."
deck=${1:-input/walker_arch.inp}
bash scripts/install_deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" >/dev/null
mkdir -p out
./build/uniarc "$deck" -o out
stem=$(basename "$deck" .inp)
echo "written: out/$stem.path out/$stem.crit out/$stem.shape"
