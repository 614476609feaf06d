#include "isocorr/render/pair_picture.h"

#include <algorithm>
#include <cmath>

#include "isocorr/output/colour_transfer.h"
#include "isocorr/output/map_files.h"
#include "isocorr/render/rasteriser.h"
#include "isocorr/render/view.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

constexpr int kMinSide = 16, kMaxSide = 8192;  // 8192^2 pixels take ~0.8 GB with the z-buffer
constexpr Rgb kBackground = {255, 255, 255};
constexpr Rgb kSeparator = {200, 200, 200};
// Light from the eye: a face turned away keeps this much of its colour, so it stays legible.
constexpr double kAmbient = 0.3;

// The mesh in the view's coordinates: x right, y up, z towards the eye.
TriangleMesh in_view_coordinates(const TriangleMesh& mesh, const ViewFrame& frame) {
  TriangleMesh moved = mesh;
  for (Vec3& p : moved.vertices) p = Vec3(p.dot(frame.right), p.dot(frame.up), -p.dot(frame.forward));
  return moved;
}

void draw_shaded(Rasteriser& rasteriser, const TriangleMesh& mesh, const std::vector<Rgb>& colours,
                 const ViewFrame& frame, const Rect& panel) {
  const std::vector<ScreenPoint> screen = fit_into(mesh, frame, panel, 0.04 * std::min(panel.width, panel.height));
  const std::vector<Vec3> normals = vertex_normals(mesh);
  std::vector<ScreenVertex> shaded(screen.size());
  for (size_t v = 0; v < screen.size(); ++v) {
    // Two-sided Lambert: meshes are not always consistently oriented.
    const double light = kAmbient + (1 - kAmbient) * std::abs(normals[v].dot(frame.forward));
    const Eigen::Vector3d colour(colours[v][0], colours[v][1], colours[v][2]);
    shaded[v] = {screen[v].x, screen[v].y, screen[v].depth, light * colour};
  }
  for (const Face& f : mesh.faces) rasteriser.draw_triangle(shaded[f[0]], shaded[f[1]], shaded[f[2]]);
}

}  // namespace

RgbImage render_pair_picture(const TriangleMesh& source, const TriangleMesh& target, const std::vector<int>& map,
                             const PairPictureOptions& options) {
  for (int side : {options.width, options.height})
    if (side < kMinSide || side > kMaxSide)
      throw InputError("picture sides must be " + std::to_string(kMinSide) + " to " + std::to_string(kMaxSide) +
                       " pixels, not " + std::to_string(side));
  check_map_fits(map, source.num_vertices(), target.num_vertices());
  const ViewFrame target_frame = view_frame(options.view, target);
  // A fixed view looks at both meshes from one side; the principal view looks at the
  // source as the map says the target is seen, whatever the two poses.
  const ViewFrame source_frame = options.view == "principal"
                                     ? view_frame_through_map(source, target, map, target_frame)
                                     : view_frame(options.view, source);
  const std::vector<Rgb> target_colours = position_colours(in_view_coordinates(target, target_frame));

  RgbImage image(options.width, options.height, kBackground);
  const int half = options.width / 2;
  for (int y = 0; y < options.height; ++y) image.set(half, y, kSeparator);
  Rasteriser rasteriser(image);
  draw_shaded(rasteriser, source, colours_through_map(map, target_colours), source_frame,
              {0, 0, static_cast<double>(half), static_cast<double>(options.height)});
  draw_shaded(rasteriser, target, target_colours, target_frame,
              {static_cast<double>(half + 1), 0, static_cast<double>(options.width - half - 1),
               static_cast<double>(options.height)});
  return image;
}

}  // namespace isocorr
