// NumPy .npy arrays: what numpy.save writes is read, what we write has numpy's layout.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "isocorr/output/npy_array.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

// A .npy file as numpy.save writes it: version 1.0, the header padded with spaces to a
// multiple of 64 bytes and ended by a newline, then the data.
std::string numpy_file(const std::string& dict, const std::string& data) {
  std::string header = dict;
  const size_t unpadded = 10 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header += '\n';
  std::string file("\x93NUMPY\x01\x00", 8);
  file += static_cast<char>(header.size() & 0xff);
  file += static_cast<char>(header.size() >> 8);
  return file + header + data;
}

std::string little_endian(std::initializer_list<int64_t> values, size_t width) {
  std::string bytes;
  for (const int64_t value : values)
    for (size_t i = 0; i < width; ++i) bytes += static_cast<char>((static_cast<uint64_t>(value) >> (8 * i)) & 0xff);
  return bytes;
}

TEST(NpyArray, Int32ArraysHaveNumpysLayout) {
  const std::string bytes = npy_bytes(std::vector<int>{3, -1, 70000});
  const std::string expected =
      numpy_file("{'descr': '<i4', 'fortran_order': False, 'shape': (3,), }", little_endian({3, -1, 70000}, 4));
  EXPECT_EQ(bytes, expected);
  EXPECT_EQ((bytes.size() - 12) % 64, 0u);  // the data starts 64-byte aligned
}

TEST(NpyArray, Float32ArraysHaveNumpysLayout) {
  const std::vector<float> values = {0.5f, 1e-3f};
  const std::string bytes = npy_bytes(values);
  const size_t data_start = bytes.size() - 8;
  EXPECT_EQ(data_start % 64, 0u);
  EXPECT_EQ(bytes.substr(0, data_start),
            numpy_file("{'descr': '<f4', 'fortran_order': False, 'shape': (2,), }", "").substr(0, data_start));
  float back[2];
  std::memcpy(back, bytes.data() + data_start, sizeof back);
  EXPECT_EQ(back[0], 0.5f);
  EXPECT_EQ(back[1], 1e-3f);
}

TEST(NpyArray, ReadsWhatItWrites) {
  const std::vector<int> values = {0, 5, -1, 2147483647};
  const std::vector<int64_t> back = parse_npy_integers(npy_bytes(values), "m.npy");
  EXPECT_EQ(back, (std::vector<int64_t>{0, 5, -1, 2147483647}));
  EXPECT_TRUE(parse_npy_integers(npy_bytes(std::vector<int>{}), "empty.npy").empty());
}

// numpy.save(np.array([...])) on Linux writes int64; a column vector and other integer
// widths load too.
TEST(NpyArray, ReadsNumpysIntegerTypesAndColumnShapes) {
  EXPECT_EQ(parse_npy_integers(numpy_file("{'descr': '<i8', 'fortran_order': False, 'shape': (3,), }",
                                          little_endian({7, -1, 1LL << 40}, 8)),
                               "a.npy"),
            (std::vector<int64_t>{7, -1, 1LL << 40}));
  EXPECT_EQ(parse_npy_integers(numpy_file("{'descr': '<u2', 'fortran_order': False, 'shape': (2, 1), }",
                                          little_endian({65535, 1}, 2)),
                               "b.npy"),
            (std::vector<int64_t>{65535, 1}));
  EXPECT_EQ(parse_npy_integers(numpy_file("{'descr': '|i1', 'fortran_order': True, 'shape': (1, 2), }",
                                          little_endian({-1, 4}, 1)),
                               "c.npy"),
            (std::vector<int64_t>{-1, 4}));
}

void expect_refused(const std::string& bytes, const std::string& says) {
  try {
    parse_npy_integers(bytes, "bad.npy");
    ADD_FAILURE() << "accepted, expected: " << says;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("bad.npy: ", 0), 0u) << message;
    EXPECT_NE(message.find(says), std::string::npos) << message;
  }
}

TEST(NpyArray, RefusesWhatIsNoIndexArrayNamingTheProblem) {
  const std::string data = little_endian({1, 2}, 4);
  expect_refused(numpy_file("{'descr': '<f4', 'fortran_order': False, 'shape': (2,), }", data), "type '<f4'");
  expect_refused(numpy_file("{'descr': '>i4', 'fortran_order': False, 'shape': (2,), }", data), "big-endian");
  expect_refused(numpy_file("{'descr': '<i4', 'fortran_order': False, 'shape': (2, 2), }", little_endian({1, 2, 3, 4}, 4)),
                 "shape (2, 2)");
  expect_refused(numpy_file("{'descr': '<i4', 'fortran_order': False, 'shape': (3,), }", data), "truncated .npy data");
  expect_refused(numpy_file("{'descr': '<i4', 'fortran_order': False, 'shape': (1,), }", data), "trailing bytes");
  expect_refused(std::string("\x93NUMPY\x01\x00\xff\x00{", 11), "truncated .npy header");
  expect_refused(std::string("\x93NUMPY\x07\x00\x00\x00", 10), "version 7");
  expect_refused(numpy_file("{'fortran_order': False, 'shape': (2,), }", data), "'descr'");
}

}  // namespace
}  // namespace isocorr
