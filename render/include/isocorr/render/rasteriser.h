// A software triangle rasteriser with a z-buffer: pictures without a GPU or a display.
// Pixel (x, y) covers [x, x+1) x [y, y+1) with y growing downwards; a triangle draws the
// pixels whose centres lie inside it or on its edges, with each corner's colour
// interpolated barycentrically. Of two surfaces on one pixel the one of least depth shows.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "isocorr/render/rgb_image.h"

namespace isocorr {

struct ScreenVertex {
  double x = 0, y = 0;        // pixels
  double depth = 0;           // distance along the viewing direction: less is nearer
  Eigen::Vector3d colour;     // 0..255 per channel
};

class Rasteriser {
 public:
  // Draws into `image`, which must outlive the rasteriser; nothing is drawn yet.
  explicit Rasteriser(RgbImage& image);

  void draw_triangle(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c);

  // Depth of what shows at (x, y); +infinity where nothing has been drawn.
  double depth_at(int x, int y) const { return depth_[static_cast<size_t>(y) * image_.width + x]; }

 private:
  RgbImage& image_;
  std::vector<double> depth_;
};

}  // namespace isocorr
