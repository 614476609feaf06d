// Matches the library's own test creature to a rotated, scaled, renumbered copy of itself
// through the installed headers and library, and checks the map against the known answer.
#include <cstdio>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/pipeline/run_match.h"
#include "isocorr/version.h"

int main() {
  const isocorr::TriangleMesh creature = isocorr::limbed_blob(3);
  const isocorr::RenumberedCopy copy = isocorr::rotated_scaled_renumbered(creature, 1.5, 11);
  const isocorr::MatchResult result = isocorr::match_meshes(creature, copy.mesh, isocorr::MatchSettings());
  const std::vector<int>& forward = result.output.forward;
  if (forward.size() != copy.permutation.size()) {
    std::fprintf(stderr, "the map has %zu entries for %zu vertices\n", forward.size(), copy.permutation.size());
    return 1;
  }
  size_t right = 0;
  for (size_t v = 0; v < forward.size(); ++v) right += forward[v] == copy.permutation[v];
  const double share = static_cast<double>(right) / forward.size();
  std::printf("isocorr %s: %zu of %zu vertices matched to their true image (%.1f%%)\n", isocorr::kVersion, right,
              forward.size(), 100 * share);
  return share >= 0.95 ? 0 : 1;
}
