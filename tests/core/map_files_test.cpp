// Map files: text and ICMAP1 binary round trips, and every malformed map read_map refuses.
#include "isocorr/output/map_files.h"
#include "isocorr/output/npy_array.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

namespace fs = std::filesystem;

class MapFiles : public ::testing::Test {
 protected:
  // One folder per test process; ctest runs every test in its own.
  MapFiles() : dir_(fs::temp_directory_path() / ("isocorr_map_files_" + std::to_string(::getpid()))) {
    fs::create_directories(dir_);
  }
  ~MapFiles() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
  // The message of the InputError read_map throws, empty when it reads the file.
  static std::string read_error(const std::string& file) {
    try {
      read_map(file);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

// An ICMAP1 file declaring `count` entries and holding `values`.
std::string binary_map(uint32_t count, const std::vector<int32_t>& values) {
  std::string bytes("ICMAP1\0\0", 8);
  auto put32 = [&](uint32_t v) {
    for (int shift = 0; shift < 32; shift += 8) bytes += static_cast<char>((v >> shift) & 0xff);
  };
  put32(count);
  for (int32_t v : values) put32(static_cast<uint32_t>(v));
  return bytes;
}

const std::vector<int> kMap = {3, 0, 70000, 2, 2147483647, 1};

TEST_F(MapFiles, TextRoundTrip) {
  write_map_text(path("a.map"), kMap);
  EXPECT_EQ(read_map(path("a.map")), kMap);
  write_map(path("b.txt"), kMap);
  EXPECT_EQ(read_map(path("b.txt")), kMap);
}

TEST_F(MapFiles, BinaryRoundTrip) {
  write_map(path("a.bin"), kMap);
  std::ifstream in(path("a.bin"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes, binary_map(6, {3, 0, 70000, 2, 2147483647, 1}));
  EXPECT_EQ(read_map(path("a.bin")), kMap);
  write_map(path("empty.bin"), {});
  EXPECT_EQ(read_map(path("empty.bin")), std::vector<int>());
}

TEST_F(MapFiles, NumpyRoundTripRecognisedByItsMagicWhateverTheName) {
  write_map(path("a.npy"), kMap);
  std::ifstream in(path("a.npy"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes, npy_bytes(kMap));
  EXPECT_EQ(read_map(path("a.npy")), kMap);
  write_map_npy(path("numpy.map"), kMap);
  EXPECT_EQ(read_map(path("numpy.map")), kMap);
}

TEST_F(MapFiles, NumpyIndicesOutsideTheIntRangeAreRefused) {
  std::string bytes = npy_bytes(std::vector<int>{1, 2});
  bytes[bytes.size() - 1] = '\xff';  // the last index becomes negative, below -1
  const std::string message = read_error(write("wild.npy", bytes));
  EXPECT_NE(message.find("vertex 1 maps to"), std::string::npos) << message;
}

TEST_F(MapFiles, ValuesAsTextOrNumpy) {
  write_values(path("c.txt"), {0.25f, 2.0f});
  std::ifstream text(path("c.txt"));
  const std::string lines((std::istreambuf_iterator<char>(text)), std::istreambuf_iterator<char>());
  EXPECT_EQ(lines, "0.25\n2\n");
  write_values(path("c.npy"), {0.25f, 2.0f});
  std::ifstream numpy(path("c.npy"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(numpy)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes, npy_bytes(std::vector<float>{0.25f, 2.0f}));
}

TEST_F(MapFiles, BinaryIsRecognisedByItsMagicWhateverTheName) {
  write_map_binary(path("binary.map"), kMap);
  EXPECT_EQ(read_map(path("binary.map")), kMap);
}

TEST_F(MapFiles, TextToleratesCarriageReturnsSpacesAndTrailingBlankLines) {
  EXPECT_EQ(read_map(write("map.txt", "3\n0\r\n 12 \n\n")), (std::vector<int>{3, 0, 12}));
  EXPECT_EQ(read_map(write("empty.txt", "")), std::vector<int>());
}

TEST_F(MapFiles, MalformedTextNamesTheLine) {
  EXPECT_NE(read_error(write("bad.txt", "3\n-2\n2\n")).find("bad.txt:2"), std::string::npos);  // negative
  EXPECT_NE(read_error(write("bad.txt", "3\n1.5\n")).find("bad.txt:2"), std::string::npos);     // not an integer
  EXPECT_NE(read_error(write("bad.txt", "3\n\n2\n")).find("bad.txt:2"), std::string::npos);     // blank inside
  EXPECT_NE(read_error(write("bad.txt", "3 4\n")).find("bad.txt:1"), std::string::npos);       // two values
  EXPECT_NE(read_error(write("bad.txt", "3\n99999999999\n")).find("bad.txt:2"), std::string::npos);  // overflow
}

TEST_F(MapFiles, MalformedBinaryNamesTheProblem) {
  const std::string full = binary_map(3, {4, 5, 6});
  const std::string short_header = read_error(write("header.bin", full.substr(0, 10)));
  EXPECT_NE(short_header.find("truncated"), std::string::npos) << short_header;
  EXPECT_NE(short_header.find("header.bin"), std::string::npos) << short_header;
  const std::string cut_magic = read_error(write("magic.bin", full.substr(0, 6)));
  EXPECT_NE(cut_magic.find("magic"), std::string::npos) << cut_magic;
  const std::string other_version = read_error(write("v2.bin", "ICMAP2" + full.substr(6)));
  EXPECT_NE(other_version.find("magic"), std::string::npos) << other_version;

  const std::string truncated = read_error(write("short.bin", full.substr(0, full.size() - 1)));
  EXPECT_NE(truncated.find("truncated"), std::string::npos) << truncated;
  EXPECT_NE(truncated.find("declares 3 indices"), std::string::npos) << truncated;
  const std::string too_few = read_error(write("count.bin", binary_map(5, {4, 5, 6})));
  EXPECT_NE(too_few.find("truncated"), std::string::npos) << too_few;
  const std::string too_many = read_error(write("long.bin", binary_map(2, {4, 5, 6})));
  EXPECT_NE(too_many.find("count mismatch"), std::string::npos) << too_many;
  // A count near 2^32 is refused from the file size, before anything is allocated.
  const std::string huge = read_error(write("huge.bin", binary_map(0xffffffffu, {1})));
  EXPECT_NE(huge.find("truncated"), std::string::npos) << huge;

  const std::string negative = read_error(write("negative.bin", binary_map(3, {4, -2, 6})));
  EXPECT_NE(negative.find("vertex 1 maps to the negative index -2"), std::string::npos) << negative;
}

TEST_F(MapFiles, MinusOneMarksAVertexWithoutCounterpartInEveryFormat) {
  for (const std::string name : {"part.txt", "part.bin", "part.npy"}) {
    write_map(path(name), {3, kNoCounterpart, 0});
    EXPECT_EQ(read_map(path(name)), (std::vector<int>{3, -1, 0})) << name;
  }
}

TEST_F(MapFiles, MissingFile) {
  EXPECT_NE(read_error(path("absent.map")).find("cannot read map file"), std::string::npos);
}

TEST(MapFit, OneTargetVertexPerSourceVertex) {
  EXPECT_NO_THROW(check_map_fits({0, 2, 2}, 3, 3));
  auto fit_error = [](const std::vector<int>& map) {
    try {
      check_map_fits(map, 3, 3);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(fit_error({0, 1}).find("2 entries but the source has 3"), std::string::npos);
  EXPECT_NE(fit_error({0, 3, 1}).find("source vertex 1 to 3, outside the target's 3"), std::string::npos);
  EXPECT_NE(fit_error({0, 1, -1}).find("source vertex 2 to -1"), std::string::npos);
  // -1 marks a vertex without counterpart, allowed only where the caller says so (the
  // reverse map of a part); no other negative index is.
  EXPECT_NO_THROW(check_map_fits({0, -1, 2}, 3, 3, true));
  EXPECT_THROW(check_map_fits({0, -2, 2}, 3, 3, true), InputError);
}

}  // namespace
}  // namespace isocorr
