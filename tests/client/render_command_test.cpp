// `isocorr render` as a user runs it on the generated example pair and its known map.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "isocorr/output/map_files.h"
#include "../render/png_reading.h"
#include "example_dataset.h"

namespace isocorr {
namespace {

namespace fs = std::filesystem;

using isocorr::testing::run_shell;
using isocorr::testing::ShellRun;

class RenderCommand : public testing::ExampleDatasetTest<4> {
 protected:
  std::string render(const fs::path& map, const std::string& extra) const {
    return std::string(ISOCORR_CLI_PATH) + " render " + (*dir_ / "meshes/creature.ply").string() + " " +
           (*dir_ / "meshes/creature_moved.ply").string() + " " + map.string() + " " + extra;
  }
};

// Pixels of the mesh (not the white background) in columns [x0, x1).
int mesh_pixels(const RgbImage& image, int x0, int x1) {
  int count = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = x0; x < x1; ++x) count += image.at(x, y) != Rgb{255, 255, 255};
  return count;
}

TEST_F(RenderCommand, WritesAPngOfTheSizeAskedWithBothMeshes) {
  const fs::path png = *dir_ / "pair.png";
  const ShellRun run = run_shell(render(*dir_ / "gt/creature_to_moved.txt", "-o " + png.string() +
                                                                                    " --width 300 --height 160"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::optional<RgbImage> image = testing::read_png_with_libpng(png.string());
  ASSERT_TRUE(image.has_value());
  EXPECT_EQ(image->width, 300);
  EXPECT_EQ(image->height, 160);
  EXPECT_GT(mesh_pixels(*image, 0, 149), 2000);    // source
  EXPECT_GT(mesh_pixels(*image, 151, 300), 2000);  // target
  EXPECT_EQ(image->at(0, 0), (Rgb{255, 255, 255}));
}

TEST_F(RenderCommand, ReadsBinaryMapsAndTakesAFixedView) {
  std::ifstream text(*dir_ / "gt/creature_to_moved.txt");
  std::vector<int> map;
  for (int v; text >> v;) map.push_back(v);
  const fs::path binary = *dir_ / "truth.bin", png = *dir_ / "front.png";
  write_map_binary(binary.string(), map);
  const ShellRun run = run_shell(render(binary, "-o " + png.string() + " --view +z --width 64 --height 32"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::optional<RgbImage> image = testing::read_png_with_libpng(png.string());
  ASSERT_TRUE(image.has_value());
  EXPECT_EQ(image->width, 64);
}

TEST_F(RenderCommand, BadInputIsExitCodeTwoWithTheReason) {
  const fs::path short_map = *dir_ / "short.map", png = *dir_ / "bad.png";
  std::ofstream(short_map) << "0\n1\n2\n";
  const ShellRun wrong_length = run_shell(render(short_map, "-o " + png.string()));
  EXPECT_EQ(wrong_length.exit_code, 2);
  EXPECT_NE(wrong_length.output.find("3 entries but the source has"), std::string::npos) << wrong_length.output;
  EXPECT_FALSE(fs::exists(png));

  const ShellRun bad_view = run_shell(render(*dir_ / "gt/creature_to_moved.txt", "-o " + png.string() + " --view up"));
  EXPECT_EQ(bad_view.exit_code, 2);
  EXPECT_NE(bad_view.output.find("--view"), std::string::npos) << bad_view.output;
  const ShellRun unwritable = run_shell(render(*dir_ / "gt/creature_to_moved.txt", "-o /nonexistent-isocorr/x.png"));
  EXPECT_EQ(unwritable.exit_code, 2);
  EXPECT_NE(unwritable.output.find("/nonexistent-isocorr/x.png"), std::string::npos) << unwritable.output;
}

// The map first, as render once took it, is refused before anything is read or written.
TEST_F(RenderCommand, TheMapFirstIsExitCodeTwoNamingTheOrder) {
  const fs::path png = *dir_ / "map_first.png";
  const ShellRun run = run_shell(std::string(ISOCORR_CLI_PATH) + " render " +
                                 (*dir_ / "gt/creature_to_moved.txt").string() + " " +
                                 (*dir_ / "meshes/creature.ply").string() + " " +
                                 (*dir_ / "meshes/creature_moved.ply").string() + " -o " + png.string());
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find("`isocorr render SOURCE TARGET MAP`"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(png));
}

}  // namespace
}  // namespace isocorr
