// PNG files of pictures, through Debian's libpng (its simplified API: 8-bit sRGB, no
// interlacing), which every viewer and browser opens.
#pragma once

#include <string>

#include "isocorr/render/rgb_image.h"

namespace isocorr {

// Writes `image` as an 8-bit RGB PNG. Throws InputError naming the file and libpng's
// reason when it cannot be written; no partial file is left behind then.
void write_png(const std::string& path, const RgbImage& image);

}  // namespace isocorr
