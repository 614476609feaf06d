#include "isocorr/render/rasteriser.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isocorr {
namespace {

// Twice the signed area of (a, b, p): positive when p lies to one side of a->b.
double edge(const ScreenVertex& a, const ScreenVertex& b, double px, double py) {
  return (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
}

unsigned char channel(double value) { return static_cast<unsigned char>(std::lround(std::clamp(value, 0.0, 255.0))); }

}  // namespace

Rasteriser::Rasteriser(RgbImage& image)
    : image_(image), depth_(static_cast<size_t>(image.width) * image.height, std::numeric_limits<double>::infinity()) {}

void Rasteriser::draw_triangle(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c) {
  for (const ScreenVertex* v : {&a, &b, &c})
    if (!std::isfinite(v->x) || !std::isfinite(v->y)) return;  // nowhere on the image
  const double area = edge(a, b, c.x, c.y);
  if (!(std::abs(area) > 1e-12)) return;  // seen edge-on: covers no pixel centre
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
  const int x1 = std::min(image_.width - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
  const int y1 = std::min(image_.height - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      // Barycentric weights of the pixel centre; all >= 0 inside, whichever way the corners turn.
      const double wa = edge(b, c, px, py) / area, wb = edge(c, a, px, py) / area, wc = edge(a, b, px, py) / area;
      if (wa < 0 || wb < 0 || wc < 0) continue;
      const double depth = wa * a.depth + wb * b.depth + wc * c.depth;
      double& nearest = depth_[static_cast<size_t>(y) * image_.width + x];
      if (!(depth < nearest)) continue;
      nearest = depth;
      const Eigen::Vector3d colour = wa * a.colour + wb * b.colour + wc * c.colour;
      image_.set(x, y, {channel(colour[0]), channel(colour[1]), channel(colour[2])});
    }
  }
}

}  // namespace isocorr
