#!/usr/bin/env bash
# The engine without the service, as a machine with only deploy/packages-engine.txt builds
# it: configures with -DISOCORR_BUILD_SERVICE=OFF and the service's packages hidden from
# CMake, at the default (portable) instruction set of installable artefacts; installs into a
# scratch prefix; checks that nothing installed links gRPC, protobuf, civetweb or libpq;
# matches the bundled example pair with the installed command line; and builds the
# find_package consumer (tests/package) against the prefix.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$here/build-engine}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)

cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DISOCORR_BUILD_SERVICE=OFF -DISOCORR_BUILD_TESTS=OFF -DISOCORR_BUILD_PYTHON=OFF \
  -DCMAKE_DISABLE_FIND_PACKAGE_gRPC=ON -DCMAKE_DISABLE_FIND_PACKAGE_Protobuf=ON "${launcher[@]}" >/dev/null
cmake --build "$build" -j "$(nproc)"
prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null

linked="$(ldd "$prefix/bin/isocorr")"
if grep -E 'grpc|protobuf|civetweb|libpq' <<<"$linked"; then
  echo "engine-only: the installed command line links a service library (above)" >&2
  exit 1
fi
if "$prefix/bin/isocorr" --help | grep -q -- '--server'; then
  echo "engine-only: the command line offers remote commands without the service" >&2
  exit 1
fi

"$build/tools/isocorr-make-examples" "$work/examples" --subdivisions 3 >/dev/null
"$prefix/bin/isocorr" match "$work/examples/meshes/creature.ply" "$work/examples/meshes/creature_moved.ply" \
  -o "$work/map.txt" >/dev/null
"$prefix/bin/isocorr" eval "$work/examples/meshes/creature.ply" "$work/examples/meshes/creature_moved.ply" \
  "$work/map.txt" --gt-kind "index_map:$work/examples/gt/creature_to_moved.txt" 2>/dev/null | tee "$work/eval.txt"
awk '/^D_grd/ { found = 1; if ($2 >= 0.01) exit 1 } END { if (!found) exit 1 }' "$work/eval.txt" || {
  echo "engine-only: the installed command line did not recover the example's map" >&2
  exit 1
}

"$here/scripts/test-package.sh" "$build"
echo "engine-only: built, installed and used without the service's packages"
