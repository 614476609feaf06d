// NumPy's .npy format for one-dimensional arrays, so that maps load with numpy.load and
// arrays saved with numpy.save load here. Written as version 1.0, little-endian, C order.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace isocorr {

// The bytes of a .npy file holding `values` as int32 ('<i4') or float32 ('<f4').
std::string npy_bytes(const std::vector<int>& values);
std::string npy_bytes(const std::vector<float>& values);

// The bytes of a .npy file holding `values` as a float64 ('<f8') array of shape
// (values.size() / columns, columns), row by row.
std::string npy_bytes(const std::vector<double>& values, size_t columns);

// Whether `bytes` starts with the .npy magic ("\x93NUMPY").
bool looks_like_npy(std::string_view bytes);

// The integers of a .npy array of any integer type numpy writes (signed or unsigned, 1 to 8
// bytes, little-endian), with shape (N,), (N, 1) or (1, N). Throws InputError naming `name`
// and what is wrong: a truncated file, another type, a shape with more than one row and
// column, a header that is not numpy's.
std::vector<int64_t> parse_npy_integers(std::string_view bytes, const std::string& name);

// A numeric .npy array of shape (N,) (one column) or (N, M), C order, as doubles row by row:
// float64, float32 or any integer type of parse_npy_integers.
struct NpyTable {
  size_t rows = 0, columns = 1;
  std::vector<double> values;
};
NpyTable parse_npy_table(std::string_view bytes, const std::string& name);

// The values, row by row, of a .npy table of exactly `columns` columns. Throws InputError
// naming `name` as parse_npy_integers does.
std::vector<double> parse_npy_rows(std::string_view bytes, const std::string& name, size_t columns);

}  // namespace isocorr
