// Meshes coloured through a map, to look at a correspondence in any mesh viewer: the
// source is coloured by position (its bounding box spread over the RGB cube, so nearby
// points look alike), and each target vertex takes the colour of its image on the source.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr {

using Rgb = std::array<unsigned char, 3>;

// One colour per vertex of `mesh`.
std::vector<Rgb> position_colours(const TriangleMesh& mesh);

// colours[map[v]] for every v; vertices mapped out of range get grey.
std::vector<Rgb> colours_through_map(const std::vector<int>& map, const std::vector<Rgb>& colours);

// Writes PREFIX + "source.ply" and PREFIX + "target.ply" (binary PLY with vertex colours).
// `reverse` maps target vertices to source vertices (isocorr's reverse map).
void write_colour_ply_pair(const std::string& prefix, const TriangleMesh& source, const TriangleMesh& target,
                           const std::vector<int>& reverse);

}  // namespace isocorr
