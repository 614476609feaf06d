// PNG files as libpng reads them back.
#include "isocorr/render/png_file.h"

#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>

#include "isocorr/util/error.h"
#include "png_reading.h"

namespace isocorr {
namespace {

namespace fs = std::filesystem;

TEST(PngFile, RoundTripsSizeAndEveryPixel) {
  RgbImage image(5, 3, Rgb{10, 20, 30});
  image.set(0, 0, {255, 0, 0});
  image.set(4, 0, {0, 255, 0});
  image.set(4, 2, {0, 0, 255});
  image.set(2, 1, {1, 2, 3});
  const fs::path path = fs::temp_directory_path() / ("isocorr_png_test_" + std::to_string(getpid()) + ".png");
  write_png(path.string(), image);
  const std::optional<RgbImage> read = testing::read_png_with_libpng(path.string());
  fs::remove(path);
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->width, 5);
  EXPECT_EQ(read->height, 3);
  EXPECT_EQ(read->at(4, 0), (Rgb{0, 255, 0}));  // rows stay top to bottom, columns left to right
  EXPECT_EQ(read->at(4, 2), (Rgb{0, 0, 255}));
  EXPECT_EQ(read->pixels, image.pixels);
}

TEST(PngFile, AnUnwritablePathIsAnInputErrorNamingIt) {
  const std::string path = "/nonexistent-isocorr-dir/pair.png";
  try {
    write_png(path, RgbImage(2, 2, Rgb{0, 0, 0}));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace isocorr
