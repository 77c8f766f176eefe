#!/usr/bin/env bash
# Install what uniarc needs on a Debian machine (run as root): gfortran, LAPACK/BLAS, CMake, Python 3
# (test tools), gnuplot (plots), Python's VTK (the ParaView file checks read every file with VTK's
# readers), numpy and pandas (the test that reads the tables with them). Does nothing when everything
# is there already.
set -euo pipefail
packages=(gfortran liblapack-dev libblas-dev cmake make python3 gnuplot-nox python3-numpy python3-pandas)
packages+=(python3-vtk9)
# scipy: the band solver of the plastic bed's reference solution (tests/regression/plastic_check.py)
packages+=(python3-scipy)
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
