// The picture of a map: source and target side by side, seen the same way, the target
// coloured by position and the source through the map, so a wrong or mirrored map shows
// as colours in the wrong places.
#pragma once

#include <string>
#include <vector>

#include "isocorr/mesh/triangle_mesh.h"
#include "isocorr/render/rgb_image.h"

namespace isocorr {

struct PairPictureOptions {
  int width = 1200, height = 600;  // the whole picture; each mesh gets one half
  // A name of view_names(): "principal" looks at the target along its principal axes and
  // at the source the same way through the map (view_frame_through_map); a fixed view
  // looks at both from that side.
  std::string view = "principal";
};

// `map` holds one target vertex per source vertex (a map file as `isocorr match` writes
// it). The target's colours spread its bounding box in the view's frame over the RGB cube
// (red grows to the right, green upwards, blue towards the eye), so left and right differ
// most; each source vertex takes its image's colour. Lambert shading by a light at the eye
// shows the shape. Throws InputError when the map does not fit the meshes or a size or
// the view is unusable.
RgbImage render_pair_picture(const TriangleMesh& source, const TriangleMesh& target, const std::vector<int>& map,
                             const PairPictureOptions& options);

}  // namespace isocorr
