#include "isocorr/output/colour_transfer.h"

#include <algorithm>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"

namespace isocorr {

std::vector<Rgb> position_colours(const TriangleMesh& mesh) {
  Vec3 low = Vec3::Constant(0), high = Vec3::Constant(0);
  if (!mesh.vertices.empty()) low = high = mesh.vertices[0];
  for (const Vec3& p : mesh.vertices) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const Vec3 extent = (high - low).cwiseMax(Vec3::Constant(1e-12));
  std::vector<Rgb> colours;
  colours.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) {
    const Vec3 unit = (p - low).cwiseQuotient(extent);
    // 30..255 rather than 0..255 so that no part turns black and hides the shading.
    Rgb rgb;
    for (int c = 0; c < 3; ++c) rgb[c] = static_cast<unsigned char>(30 + 225 * std::clamp(unit[c], 0.0, 1.0));
    colours.push_back(rgb);
  }
  return colours;
}

std::vector<Rgb> colours_through_map(const std::vector<int>& map, const std::vector<Rgb>& colours) {
  std::vector<Rgb> pulled(map.size(), Rgb{128, 128, 128});
  for (size_t v = 0; v < map.size(); ++v)
    if (map[v] >= 0 && static_cast<size_t>(map[v]) < colours.size()) pulled[v] = colours[map[v]];
  return pulled;
}

void write_colour_ply_pair(const std::string& prefix, const TriangleMesh& source, const TriangleMesh& target,
                           const std::vector<int>& reverse) {
  if (reverse.size() != target.vertices.size())
    throw InputError("the map has " + std::to_string(reverse.size()) + " entries but the target mesh " +
                     std::to_string(target.vertices.size()) + " vertices");
  const std::vector<Rgb> source_colours = position_colours(source);
  write_ply(prefix + "source.ply", source, source_colours);
  write_ply(prefix + "target.ply", target, colours_through_map(reverse, source_colours));
}

}  // namespace isocorr
