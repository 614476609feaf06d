#!/usr/bin/env bash
# Builds and runs the whole test suite (unit, CLI and end-to-end on ../shared/data).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
"$here/scripts/build.sh"
cd "$here/build"
ctest --output-on-failure -j 1 "$@"
