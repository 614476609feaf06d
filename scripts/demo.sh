#!/usr/bin/env bash
# End to end on the project's own example meshes: builds, generates an asymmetric shape
# and a rotated, scaled, renumbered copy, matches them and scores the map.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
"$here/scripts/build.sh"
out="$here/build/demo"
"$here/build/tools/isocorr-make-examples" "$out"
"$here/build/client/isocorr" match "$out/meshes/creature.ply" "$out/meshes/creature_moved.ply" \
  -o "$out/creature.map" --reverse-out "$out/creature.reverse.map" --report "$out/creature.report.json"
"$here/build/client/isocorr" eval meshes/creature.ply meshes/creature_moved.ply "$out/creature.map" \
  --dataset "$out"
echo "demo: map, reverse map and JSON report are in $out"
