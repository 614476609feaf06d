// Reads a PNG back with libpng itself, so the tests check the files the way viewers see them.
#pragma once

#include <png.h>

#include <cstring>
#include <optional>
#include <string>

#include "isocorr/render/rgb_image.h"

namespace isocorr::testing {

// The picture as 8-bit RGB, or nullopt when libpng cannot read the file.
inline std::optional<RgbImage> read_png_with_libpng(const std::string& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) return std::nullopt;
  png.format = PNG_FORMAT_RGB;
  RgbImage image(static_cast<int>(png.width), static_cast<int>(png.height), Rgb{0, 0, 0});
  if (!png_image_finish_read(&png, nullptr, image.pixels.data(), 0, nullptr)) return std::nullopt;
  return image;
}

}  // namespace isocorr::testing
