#!/usr/bin/env bash
# Builds and runs the whole test suite (unit, CLI and end-to-end on ../shared/data), after
# checking the deploy files.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
"$here/scripts/build.sh"
# The deploy files, parsed and checked against the server just built.
"$here/scripts/check-deploy.sh"
cd "$here/build"
ctest --output-on-failure -j 1 "$@"
