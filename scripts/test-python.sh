#!/usr/bin/env bash
# Installs the Python package from the repository into a fresh virtual environment, as a
# user would (pip, offline, with Debian's numpy and pybind11), and runs its tests. The
# extension comes from the build folder given (build/ by default), configured with
# -DISOCORR_BUILD_PYTHON=ON, so that it is not compiled twice.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$here/build}" && pwd)"
environment="$build/python-env"
rm -rf "$environment"
# Debian's interpreter: python3-numpy and python3-pytest are its packages.
/usr/bin/python3 -m venv --system-site-packages "$environment"
ISOCORR_CMAKE_BUILD_DIR="$build" "$environment/bin/pip" install --quiet --no-build-isolation --no-deps "$here/python"
# From outside the repository, so that `import isocorr` finds the installed package.
cd "$build"
ISOCORR_BUILD_DIR="$build" "$environment/bin/python" -m pytest -q -p no:cacheprovider "$here/python/tests"
