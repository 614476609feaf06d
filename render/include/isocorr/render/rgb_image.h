// An 8-bit RGB picture in memory, rows from top to bottom, as PNG files store them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "isocorr/output/colour_transfer.h"

namespace isocorr {

struct RgbImage {
  RgbImage(int width, int height, Rgb background)
      : width(width), height(height), pixels(static_cast<size_t>(width) * height * 3) {
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = background[i % 3];
  }

  Rgb at(int x, int y) const {
    const uint8_t* p = &pixels[offset(x, y)];
    return {p[0], p[1], p[2]};
  }
  void set(int x, int y, Rgb colour) {
    uint8_t* p = &pixels[offset(x, y)];
    p[0] = colour[0], p[1] = colour[1], p[2] = colour[2];
  }

  int width, height;
  std::vector<uint8_t> pixels;  // width * height * 3 bytes, R G B per pixel

 private:
  size_t offset(int x, int y) const { return (static_cast<size_t>(y) * width + x) * 3; }
};

}  // namespace isocorr
