// PLY: a reader for ASCII and binary (either byte order) files, and the binary
// little-endian writer.
#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"
#include "mesh_builder.h"
#include "mesh_formats.h"
#include "text_scanning.h"

namespace isocorr {
namespace mesh_formats {
namespace {

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyEncoding { Ascii, LittleEndian, BigEndian };

bool scalar_from_name(string_view name, Scalar& type) {
  static constexpr std::pair<string_view, Scalar> kNames[] = {
      {"char", Scalar::Int8},      {"int8", Scalar::Int8},       {"uchar", Scalar::UInt8},
      {"uint8", Scalar::UInt8},    {"short", Scalar::Int16},     {"int16", Scalar::Int16},
      {"ushort", Scalar::UInt16},  {"uint16", Scalar::UInt16},   {"int", Scalar::Int32},
      {"int32", Scalar::Int32},    {"uint", Scalar::UInt32},     {"uint32", Scalar::UInt32},
      {"float", Scalar::Float32},  {"float32", Scalar::Float32}, {"double", Scalar::Float64},
      {"float64", Scalar::Float64}};
  for (const auto& [candidate, value] : kNames)
    if (candidate == name) return type = value, true;
  return false;
}

size_t scalar_size(Scalar type) {
  switch (type) {
    case Scalar::Int8: case Scalar::UInt8: return 1;
    case Scalar::Int16: case Scalar::UInt16: return 2;
    case Scalar::Int32: case Scalar::UInt32: case Scalar::Float32: return 4;
    case Scalar::Float64: return 8;
  }
  return 1;
}

struct PlyProperty {
  std::string name;
  Scalar type = Scalar::Float32;
  bool is_list = false;
  Scalar count_type = Scalar::UInt8;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;

  int find(string_view property) const {
    for (size_t p = 0; p < properties.size(); ++p)
      if (properties[p].name == property) return static_cast<int>(p);
    return -1;
  }
  // Fewest bytes one record can take: a token plus separator per ASCII value.
  size_t min_record_bytes(PlyEncoding encoding) const {
    size_t bytes = 0;
    for (const PlyProperty& p : properties)
      bytes += encoding == PlyEncoding::Ascii ? 2 : scalar_size(p.is_list ? p.count_type : p.type);
    return bytes;
  }
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::Ascii;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;
};

PlyHeader parse_ply_header(string_view bytes) {
  constexpr const char* kFormat = "PLY";
  PlyHeader header;
  size_t position = 0;
  long long line_number = 0;
  auto next_line = [&](string_view& line) {
    if (position >= bytes.size()) return false;
    const size_t end = std::min(bytes.find('\n', position), bytes.size());
    line = bytes.substr(position, end - position);
    position = std::min(end + 1, bytes.size());
    ++line_number;
    return true;
  };
  string_view line, keyword, token;
  if (!next_line(line) || (line != "ply" && line != "ply\r")) fail(kFormat, "the file does not start with 'ply'");
  bool has_format = false;
  for (;;) {
    if (!next_line(line)) fail(kFormat, "the header has no end_header line (truncated?)");
    Tokens words(line);
    if (!words.next(keyword) || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") break;
    if (keyword == "format") {
      words.next(token);
      if (token == "ascii") header.encoding = PlyEncoding::Ascii;
      else if (token == "binary_little_endian") header.encoding = PlyEncoding::LittleEndian;
      else if (token == "binary_big_endian") header.encoding = PlyEncoding::BigEndian;
      else fail(kFormat, cat("unknown format ", shown(token), " on header line ", line_number));
      has_format = true;
    } else if (keyword == "element") {
      PlyElement element;
      words.next(token);
      element.name = token;
      if (!words.next(token) || !parse_integer(token, element.count) || element.count < 0)
        fail(kFormat, cat("header line ", line_number, ": element ", shown(element.name),
                          " needs a non-negative count, not ", shown(token)));
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) fail(kFormat, cat("header line ", line_number, ": a property before any element"));
      PlyProperty property;
      words.next(token);
      if (token == "list") {
        property.is_list = true;
        words.next(token);
        if (!scalar_from_name(token, property.count_type))
          fail(kFormat, cat("header line ", line_number, ": unknown list count type ", shown(token)));
        words.next(token);
      }
      if (!scalar_from_name(token, property.type))
        fail(kFormat, cat("header line ", line_number, ": unknown property type ", shown(token)));
      if (!words.next(token)) fail(kFormat, cat("header line ", line_number, ": a property without a name"));
      property.name = token;
      header.elements.back().properties.push_back(std::move(property));
    } else {
      fail(kFormat, cat("header line ", line_number, ": unknown keyword ", shown(keyword)));
    }
  }
  if (!has_format) fail(kFormat, "the header has no format line");
  header.body_offset = position;

  // Every record needs some bytes, so the counts cannot exceed what follows the header.
  size_t available = bytes.size() - position + (header.encoding == PlyEncoding::Ascii ? 1 : 0);
  for (const PlyElement& element : header.elements) {
    const size_t record = element.min_record_bytes(header.encoding);
    if (record == 0) continue;
    if (static_cast<unsigned long long>(element.count) > available / record)
      fail(kFormat, cat("the header declares ", element.count, " '", element.name, "' records but only ",
                        bytes.size() - position, " bytes of data follow (truncated or corrupt?)"));
    available -= static_cast<size_t>(element.count) * record;
  }
  return header;
}

template <class T>
T load_scalar(const char* bytes, bool swap) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, bytes, sizeof(T));
  if (swap) std::reverse(raw, raw + sizeof(T));
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

// Reads the body's values in file order: ASCII tokens or binary numbers of either byte order.
class PlyValues {
 public:
  PlyValues(string_view body, PlyEncoding encoding)
      : data_(body),
        encoding_(encoding),
        swap_((encoding == PlyEncoding::BigEndian) != (std::endian::native == std::endian::big)) {}

  // The record being read, for messages.
  void at_record(const std::string& element, long long index) { element_ = &element, index_ = index; }

  double read(Scalar type) {
    if (encoding_ == PlyEncoding::Ascii) return read_text();
    const size_t size = scalar_size(type);
    if (data_.size() - position_ < size) truncated();
    const char* at = data_.data() + position_;
    position_ += size;
    switch (type) {
      case Scalar::Int8: return load_scalar<std::int8_t>(at, swap_);
      case Scalar::UInt8: return load_scalar<std::uint8_t>(at, swap_);
      case Scalar::Int16: return load_scalar<std::int16_t>(at, swap_);
      case Scalar::UInt16: return load_scalar<std::uint16_t>(at, swap_);
      case Scalar::Int32: return load_scalar<std::int32_t>(at, swap_);
      case Scalar::UInt32: return load_scalar<std::uint32_t>(at, swap_);
      case Scalar::Float32: return load_scalar<float>(at, swap_);
      case Scalar::Float64: return load_scalar<double>(at, swap_);
    }
    return 0.0;
  }

  // A whole number (list length or vertex index) stored in any scalar type.
  long long read_integer(Scalar type, const char* what) {
    const double value = read(type);
    if (!(std::abs(value) < 9e15) || value != std::trunc(value))
      fail("PLY", cat(*element_, ' ', index_, " has the ", what, ' ', value, ", which is not an integer"));
    return static_cast<long long>(value);
  }

  // Makes sure `count` values of `type` are still there (binary) before anyone reserves them.
  void require(Scalar type, long long count) {
    if (encoding_ != PlyEncoding::Ascii && static_cast<size_t>(count) > (data_.size() - position_) / scalar_size(type))
      truncated();
  }

  void skip(const PlyProperty& property) {
    const long long count = property.is_list ? read_integer(property.count_type, "list length") : 1;
    if (count < 0) fail("PLY", cat(*element_, ' ', index_, " has a negative list length"));
    require(property.type, count);
    if (encoding_ != PlyEncoding::Ascii) position_ += static_cast<size_t>(count) * scalar_size(property.type);
    else
      for (long long i = 0; i < count; ++i) read_text();
  }

 private:
  double read_text() {
    while (position_ < data_.size() && is_space(data_[position_])) ++position_;
    const size_t begin = position_;
    while (position_ < data_.size() && !is_space(data_[position_])) ++position_;
    if (begin == position_) truncated();
    const string_view token = data_.substr(begin, position_ - begin);
    double value = 0.0;
    if (!parse_number(token, value))
      fail("PLY", cat(*element_, ' ', index_, " contains ", shown(token), ", which is not a number"));
    return value;
  }

  [[noreturn]] void truncated() const {
    fail("PLY", cat("the data ends inside ", *element_, ' ', index_, " (truncated?)"));
  }

  string_view data_;
  size_t position_ = 0;
  PlyEncoding encoding_;
  bool swap_;
  const std::string* element_ = nullptr;
  long long index_ = 0;
};

}  // namespace

LoadedMesh parse_ply(string_view bytes) {
  constexpr const char* kFormat = "PLY";
  const PlyHeader header = parse_ply_header(bytes);
  const PlyElement* vertex_element = nullptr;
  const PlyElement* face_element = nullptr;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex" && !vertex_element) vertex_element = &element;
    if (element.name == "face" && !face_element) face_element = &element;
  }
  if (!vertex_element) fail(kFormat, "the header declares no vertex element");
  if (!face_element || face_element->count == 0) fail(kFormat, "the file has no faces");
  int xyz[3];
  for (int axis = 0; axis < 3; ++axis) {
    const char name[2] = {static_cast<char>('x' + axis), '\0'};
    xyz[axis] = vertex_element->find(name);
    if (xyz[axis] < 0 || vertex_element->properties[xyz[axis]].is_list)
      fail(kFormat, cat("the vertex element has no scalar property '", name, "'"));
  }
  int corner_list = face_element->find("vertex_indices");
  if (corner_list < 0) corner_list = face_element->find("vertex_index");
  if (corner_list < 0 || !face_element->properties[corner_list].is_list)
    fail(kFormat, "the face element has no vertex_indices list");
  if (vertex_element->count > INT_MAX) fail(kFormat, cat("too many vertices (", vertex_element->count, ")"));

  MeshBuilder builder(kFormat, 0);
  builder.expect(vertex_element->count, face_element->count);
  PlyValues values(bytes.substr(header.body_offset), header.encoding);
  int elements_left = 2;  // trailing elements after vertices and faces need not be read
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;  // records without properties take no bytes
    const bool is_vertex = &element == vertex_element, is_face = &element == face_element;
    for (long long record = 0; record < element.count; ++record) {
      values.at_record(element.name, record);
      double coordinates[3] = {0, 0, 0};
      for (int p = 0; p < static_cast<int>(element.properties.size()); ++p) {
        const PlyProperty& property = element.properties[p];
        if (is_face && p == corner_list) {
          const long long count = values.read_integer(property.count_type, "corner count");
          builder.require_corner_count(count, {"face", record});
          values.require(property.type, count);
          builder.begin_polygon({"face", record});
          for (long long k = 0; k < count; ++k) builder.add_corner(values.read_integer(property.type, "vertex index"));
          builder.end_polygon();
        } else if (is_vertex && !property.is_list && (p == xyz[0] || p == xyz[1] || p == xyz[2])) {
          coordinates[p == xyz[0] ? 0 : p == xyz[1] ? 1 : 2] = values.read(property.type);
        } else {
          values.skip(property);
        }
      }
      if (is_vertex) builder.add_vertex(coordinates[0], coordinates[1], coordinates[2], {"vertex", record});
    }
    if ((is_vertex || is_face) && --elements_left == 0) break;
  }
  const char* names[] = {"ply-ascii", "ply-binary-le", "ply-binary-be"};
  return builder.finish(names[static_cast<int>(header.encoding)]);
}

}  // namespace mesh_formats

namespace {

void append_le(std::string& out, const void* value, size_t size) {
  const char* bytes = static_cast<const char*>(value);
  if constexpr (std::endian::native == std::endian::little) {
    out.append(bytes, size);
  } else {
    for (size_t i = size; i-- > 0;) out += bytes[i];
  }
}

}  // namespace

void write_ply(const std::string& path, const TriangleMesh& mesh,
               const std::vector<std::array<unsigned char, 3>>& colours) {
  using mesh_formats::cat;
  if (!colours.empty() && colours.size() != mesh.vertices.size())
    throw std::invalid_argument(cat("write_ply: ", colours.size(), " colours for ", mesh.vertices.size(), " vertices"));
  std::string out = cat("ply\nformat binary_little_endian 1.0\ncomment written by isocorr\nelement vertex ",
                        mesh.vertices.size(), "\nproperty float x\nproperty float y\nproperty float z\n",
                        colours.empty() ? "" : "property uchar red\nproperty uchar green\nproperty uchar blue\n",
                        "element face ", mesh.faces.size(), "\nproperty list uchar int vertex_indices\nend_header\n");
  out.reserve(out.size() + mesh.vertices.size() * 15 + mesh.faces.size() * 13);
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      const float coordinate = static_cast<float>(mesh.vertices[v][axis]);
      append_le(out, &coordinate, sizeof coordinate);
    }
    if (!colours.empty()) out.append(reinterpret_cast<const char*>(colours[v].data()), 3);
  }
  for (const Face& face : mesh.faces) {
    out += static_cast<char>(3);
    for (int index : face) {
      const std::int32_t value = index;
      append_le(out, &value, sizeof value);
    }
  }
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(out.data(), static_cast<std::streamsize>(out.size()));
  file.close();
  if (!file) throw InputError(cat("cannot write PLY file '", path, "'"));
}

}  // namespace isocorr

namespace isocorr::mesh_formats {

std::vector<double> ply_vertex_properties(string_view bytes, const std::vector<std::string>& names) {
  const PlyHeader header = parse_ply_header(bytes);
  const auto vertex_element = std::find_if(header.elements.begin(), header.elements.end(),
                                           [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex_element == header.elements.end()) fail("PLY", "the header declares no vertex element");
  // Per property of the vertex element, the column it fills (-1: none).
  std::vector<int> column_of(vertex_element->properties.size(), -1);
  for (size_t c = 0; c < names.size(); ++c) {
    const int p = vertex_element->find(names[c]);
    if (p < 0 || vertex_element->properties[p].is_list) {
      std::string present;
      for (const PlyProperty& property : vertex_element->properties) present += " " + property.name;
      fail("PLY", cat("the vertex element has no scalar property '", names[c], "' (it has:", present, ")"));
    }
    column_of[p] = static_cast<int>(c);
  }
  std::vector<double> table;
  PlyValues values(bytes.substr(header.body_offset), header.encoding);
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;
    const bool is_vertex = &element == &*vertex_element;
    std::vector<double> row(names.size());
    for (long long record = 0; record < element.count; ++record) {
      values.at_record(element.name, record);
      for (size_t p = 0; p < element.properties.size(); ++p) {
        if (is_vertex && column_of[p] >= 0) row[column_of[p]] = values.read(element.properties[p].type);
        else values.skip(element.properties[p]);
      }
      if (is_vertex) table.insert(table.end(), row.begin(), row.end());
    }
    if (is_vertex) break;
  }
  return table;
}

}  // namespace isocorr::mesh_formats
