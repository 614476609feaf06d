#!/usr/bin/env bash
# Installs the engine library from build/ into a scratch prefix and builds and runs
# tests/package, a project outside this tree that finds it with find_package(isocorr).
# Proves the installed headers, library and CMake package are complete on their own.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$here/tests/package" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/isocorr_consumer"
