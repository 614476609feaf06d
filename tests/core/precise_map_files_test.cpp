// Precise map files: text and .npy round trips, and errors that name the line.
#include "isocorr/output/precise_map_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

namespace fs = std::filesystem;

class PreciseMapFiles : public ::testing::Test {
 protected:
  fs::path dir_ = fs::temp_directory_path() / ("isocorr-precise-" + std::to_string(::getpid()));
  void SetUp() override { fs::create_directories(dir_); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write_text(const std::string& text) const {
    const std::string path = (dir_ / "map.txt").string();
    std::ofstream(path) << text;
    return path;
  }
};

const PreciseMap kMap = {{3, {0.25f, 0.5f, 0.25f}}, {-1, {1, 0, 0}}, {0, {1, 0, 0}}};

TEST_F(PreciseMapFiles, TextAndNpyRoundTrip) {
  for (const char* name : {"map.txt", "map.npy"}) {
    const std::string path = (dir_ / name).string();
    write_precise_map(path, kMap);
    const PreciseMap back = read_precise_map(path);
    ASSERT_EQ(back.size(), kMap.size()) << name;
    for (size_t i = 0; i < kMap.size(); ++i) {
      EXPECT_EQ(back[i].face, kMap[i].face) << name;
      if (kMap[i].face >= 0) EXPECT_EQ(back[i].weights, kMap[i].weights) << name;
    }
  }
}

TEST_F(PreciseMapFiles, BadLinesAreNamed) {
  const std::pair<const char*, const char*> cases[] = {
      {"0 1 0 0\n2 0.5 0.5\n", "map.txt:2"},
      {"0 1 0 0\n1.5 1 0 0\n", "map.txt:2: the face"},
      {"0 0.9 0.3 0\n", "sum to"},
      {"0 -0.5 1.5 0\n", "not a barycentric weight"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      read_precise_map(write_text(text));
      ADD_FAILURE() << "accepted " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

TEST_F(PreciseMapFiles, AMapThatDoesNotFitIsRefused) {
  EXPECT_THROW(check_precise_map_fits(kMap, 4, 10), InputError);
  EXPECT_THROW(check_precise_map_fits(kMap, 3, 3), InputError);
  EXPECT_NO_THROW(check_precise_map_fits(kMap, 3, 4));
}

}  // namespace
}  // namespace isocorr
