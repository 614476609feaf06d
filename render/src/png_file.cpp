#include "isocorr/render/png_file.h"

#include <png.h>

#include <cstring>

#include "isocorr/util/error.h"

namespace isocorr {

void write_png(const std::string& path, const RgbImage& image) {
  png_image png;
  std::memset(&png, 0, sizeof png);  // the simplified API's documented initialisation
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  // libpng removes the file itself when writing fails part-way.
  if (!png_image_write_to_file(&png, path.c_str(), 0, image.pixels.data(), 0, nullptr))
    throw InputError("cannot write '" + path + "': " + png.message);
  png_image_free(&png);
}

}  // namespace isocorr
