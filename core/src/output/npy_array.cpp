#include "isocorr/output/npy_array.h"

#include <cstring>
#include <limits>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

constexpr std::string_view kMagic("\x93NUMPY", 6);
// numpy aligns the data to 64 bytes: magic, version, header length, header, newline.
constexpr size_t kAlignment = 64;

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw InputError(name + ": " + what);
}

// `shape`: numpy's tuple text, "(N,)" or "(N, M)".
std::string file_header(const std::string& descr, const std::string& shape) {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
  const size_t unpadded = kMagic.size() + 2 + 2 + dict.size() + 1;
  dict.append((kAlignment - unpadded % kAlignment) % kAlignment, ' ');
  dict += '\n';
  std::string header(kMagic);
  header += '\x01';  // version 1.0: a 16-bit header length
  header += '\x00';
  header += static_cast<char>(dict.size() & 0xff);
  header += static_cast<char>(dict.size() >> 8);
  return header + dict;
}

void append_le32(std::string& out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((value >> (8 * i)) & 0xff);
}

uint64_t load_le(std::string_view bytes, size_t at, size_t width) {
  uint64_t value = 0;
  for (size_t i = width; i-- > 0;) value = value << 8 | static_cast<unsigned char>(bytes[at + i]);
  return value;
}

// The text after `key` up to the next `,` or `}` outside parentheses, trimmed; empty when
// the key is missing.
std::string header_value(const std::string& header, const std::string& key) {
  const size_t at = header.find("'" + key + "'");
  if (at == std::string::npos) return "";
  size_t begin = header.find(':', at);
  if (begin == std::string::npos) return "";
  ++begin;
  int depth = 0;
  size_t end = begin;
  for (; end < header.size(); ++end) {
    const char c = header[end];
    if (c == '(') ++depth;
    else if (c == ')') --depth;
    else if ((c == ',' || c == '}') && depth == 0) break;
  }
  const size_t first = header.find_first_not_of(" ", begin);
  const size_t last = header.find_last_not_of(" ", end - 1);
  return first == std::string::npos || first > last ? "" : header.substr(first, last - first + 1);
}

// "(N,)", "(N, 1)" or "(1, N)" -> N; anything else fails.
size_t element_count(const std::string& shape, const std::string& name) {
  if (shape.size() < 2 || shape.front() != '(' || shape.back() != ')')
    fail(name, "the .npy header has no shape tuple");
  // Dimensions of up to 15 digits: larger than any file, and no overflow below.
  constexpr size_t kMaxDigits = 15;
  std::vector<uint64_t> dims;
  std::string digits;
  auto end_dimension = [&] {
    if (digits.empty()) return;
    if (digits.size() > kMaxDigits) fail(name, "the .npy shape " + shape + " is larger than any file");
    dims.push_back(std::stoull(digits));
    digits.clear();
  };
  for (size_t i = 1; i + 1 < shape.size(); ++i) {
    const char c = shape[i];
    if (c >= '0' && c <= '9') digits += c;
    else if (c == ',' || c == ' ') end_dimension();
    else fail(name, "unreadable .npy shape " + shape);
  }
  end_dimension();
  if (dims.size() == 1) return dims[0];
  if (dims.size() == 2 && (dims[0] == 1 || dims[1] == 1)) return dims[0] * dims[1];
  fail(name, "a map is one index per vertex: expected a .npy array of shape (N,), found shape " + shape);
}

// A .npy file's header dictionary and its data.
struct NpyFile {
  std::string header;
  std::string_view data;
};

NpyFile split_npy(std::string_view bytes, const std::string& name) {
  if (!looks_like_npy(bytes)) fail(name, "not a .npy file (no \\x93NUMPY magic)");
  if (bytes.size() < 10) fail(name, "truncated .npy file: " + std::to_string(bytes.size()) + " bytes");
  const int major = static_cast<unsigned char>(bytes[6]);
  if (major < 1 || major > 3) fail(name, "unsupported .npy version " + std::to_string(major));
  const size_t length_bytes = major == 1 ? 2 : 4;
  const size_t header_start = 8 + length_bytes;
  if (bytes.size() < header_start) fail(name, "truncated .npy header");
  const uint64_t header_length = load_le(bytes, 8, length_bytes);
  if (bytes.size() < header_start + header_length)
    fail(name, "truncated .npy header: it declares " + std::to_string(header_length) + " bytes");
  return {std::string(bytes.substr(header_start, header_length)), bytes.substr(header_start + header_length)};
}

}  // namespace

std::string npy_bytes(const std::vector<int>& values) {
  std::string out = file_header("<i4", "(" + std::to_string(values.size()) + ",)");
  out.reserve(out.size() + 4 * values.size());
  for (const int v : values) append_le32(out, static_cast<uint32_t>(v));
  return out;
}

std::string npy_bytes(const std::vector<float>& values) {
  std::string out = file_header("<f4", "(" + std::to_string(values.size()) + ",)");
  out.reserve(out.size() + 4 * values.size());
  for (const float v : values) {
    uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    append_le32(out, bits);
  }
  return out;
}

bool looks_like_npy(std::string_view bytes) { return bytes.starts_with(kMagic); }

std::vector<int64_t> parse_npy_integers(std::string_view bytes, const std::string& name) {
  const NpyFile file = split_npy(bytes, name);
  const std::string& header = file.header;
  const std::string descr = header_value(header, "descr");
  // '<i4', '|u1', '=i8': byte order, kind, size; quoted.
  if (descr.size() < 5 || descr.front() != '\'' || descr.back() != '\'')
    fail(name, "the .npy header has no readable 'descr'");
  const char order = descr[1], kind = descr[2];
  const std::string size_text = descr.substr(3, descr.size() - 4);
  if (order == '>') fail(name, "big-endian .npy arrays are not read: save it as '<i4' (numpy.astype('<i4'))");
  const bool is_signed = kind == 'i';
  const size_t width = size_text == "1" ? 1 : size_text == "2" ? 2 : size_text == "4" ? 4 : size_text == "8" ? 8 : 0;
  if ((kind != 'i' && kind != 'u') || width == 0 || (order != '<' && order != '|' && order != '='))
    fail(name, "a map holds integer vertex indices; this .npy array has type " + descr);
  const size_t count = element_count(header_value(header, "shape"), name);

  const std::string_view data = file.data;
  if (data.size() != count * width)
    fail(name, std::string(data.size() < count * width ? "truncated .npy data" : "trailing bytes after the .npy data") +
                   ": the header declares " + std::to_string(count) + " values of " + std::to_string(width) +
                   " bytes, the file has " + std::to_string(data.size()) + " bytes of data");
  std::vector<int64_t> values(count);
  for (size_t k = 0; k < count; ++k) {
    uint64_t raw = load_le(data, k * width, width);
    if (is_signed && width < 8 && (raw >> (8 * width - 1)) & 1) raw |= ~uint64_t{0} << (8 * width);  // sign-extend
    values[k] = !is_signed && raw > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())
                    ? std::numeric_limits<int64_t>::max()
                    : static_cast<int64_t>(raw);
  }
  return values;
}

std::string npy_bytes(const std::vector<double>& values, size_t columns) {
  std::string out = file_header("<f8", "(" + std::to_string(values.size() / columns) + ", " + std::to_string(columns) + ")");
  out.reserve(out.size() + 8 * values.size());
  for (const double v : values) {
    uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    for (int i = 0; i < 8; ++i) out += static_cast<char>((bits >> (8 * i)) & 0xff);
  }
  return out;
}

NpyTable parse_npy_table(std::string_view bytes, const std::string& name) {
  const NpyFile file = split_npy(bytes, name);
  const std::string descr = header_value(file.header, "descr");
  if (descr.size() < 5 || descr.front() != '\'' || descr.back() != '\'')
    fail(name, "the .npy header has no readable 'descr'");
  const char order = descr[1], kind = descr[2];
  const std::string size_text = descr.substr(3, descr.size() - 4);
  const size_t width = size_text == "1" ? 1 : size_text == "2" ? 2 : size_text == "4" ? 4 : size_text == "8" ? 8 : 0;
  const bool is_float = kind == 'f' && (width == 4 || width == 8);
  if (order == '>' || (kind != 'f' && kind != 'i' && kind != 'u') || width == 0 || (kind == 'f' && !is_float))
    fail(name, "expected a little-endian numeric .npy array, found type " + descr);
  if (header_value(file.header, "fortran_order") != "False") fail(name, "a Fortran-ordered .npy array is not read");
  // (N,) or (N, M): the count of the first dimension, and the columns.
  const std::string shape = header_value(file.header, "shape");
  NpyTable table;
  const size_t comma = shape.find(',');
  const std::string second = comma == std::string::npos ? "" : shape.substr(comma + 1, shape.size() - comma - 2);
  if (second.find_first_not_of(" ") != std::string::npos) {
    table.columns = element_count("(" + second + ",)", name);
    table.rows = element_count(shape.substr(0, comma) + ",)", name);
  } else {
    table.rows = element_count(shape, name);
  }
  if (table.columns == 0 || file.data.size() != table.rows * table.columns * width)
    fail(name, "the .npy header declares shape " + shape + " of " + std::to_string(width) + "-byte values, the file has " +
                   std::to_string(file.data.size()) + " bytes of data");
  table.values.resize(table.rows * table.columns);
  for (size_t k = 0; k < table.values.size(); ++k) {
    uint64_t raw = load_le(file.data, k * width, width);
    if (kind == 'f' && width == 8) {
      std::memcpy(&table.values[k], &raw, 8);
    } else if (kind == 'f') {
      const auto narrow = static_cast<uint32_t>(raw);
      float f = 0;
      std::memcpy(&f, &narrow, 4);
      table.values[k] = f;
    } else {
      if (kind == 'i' && width < 8 && (raw >> (8 * width - 1)) & 1) raw |= ~uint64_t{0} << (8 * width);
      table.values[k] = kind == 'i' ? static_cast<double>(static_cast<int64_t>(raw)) : static_cast<double>(raw);
    }
  }
  return table;
}

std::vector<double> parse_npy_rows(std::string_view bytes, const std::string& name, size_t columns) {
  NpyTable table = parse_npy_table(bytes, name);
  if (table.columns != columns)
    fail(name, "expected a .npy array of " + std::to_string(columns) + " columns, found " + std::to_string(table.columns));
  return std::move(table.values);
}

}  // namespace isocorr
