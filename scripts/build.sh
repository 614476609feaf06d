#!/usr/bin/env bash
# Configures and builds everything into build/ (Release). Uses both cores.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
"$here/scripts/install-deps.sh"
# The widest instruction set this machine runs: the tests and the benchmarks measure it. The
# Python module too: the Python tests install the package from this build.
cmake -S "$here" -B "$here/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DISOCORR_ARCH=auto -DISOCORR_BUILD_PYTHON=ON \
  >/dev/null
cmake --build "$here/build" -j "$(nproc)"
