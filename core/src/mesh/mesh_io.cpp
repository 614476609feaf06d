// Our own OFF, OBJ and PLY readers and a binary PLY writer. Mesh files come from users, so
// every malformed input becomes an InputError naming the problem, and header counts are
// checked against the bytes that follow before anything is allocated.
#include "isocorr/mesh/mesh_io.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "isocorr/util/error.h"

namespace isocorr {

namespace {

using std::string_view;

template <class... Parts>
std::string cat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

[[noreturn]] void fail(string_view format, const std::string& message) {
  throw InputError(cat(format, ": ", message));
}

// File bytes echoed in messages: printable, and short even for binary garbage.
std::string shown(string_view token) {
  std::string out = "'";
  for (char c : token.substr(0, 24)) out += (c >= 32 && c < 127) ? c : '?';
  return out + (token.size() > 24 ? "...'" : "'");
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// Splits text at whitespace; tokens are views into the file's bytes.
class Tokens {
 public:
  explicit Tokens(string_view text) : rest_(text) {}
  bool next(string_view& token) {
    size_t begin = 0;
    while (begin < rest_.size() && is_space(rest_[begin])) ++begin;
    size_t end = begin;
    while (end < rest_.size() && !is_space(rest_[end])) ++end;
    token = rest_.substr(begin, end - begin);
    rest_.remove_prefix(end);
    return !token.empty();
  }

 private:
  string_view rest_;
};

// Yields the non-blank lines of a text with '#' comments removed, counting line numbers.
class Lines {
 public:
  explicit Lines(string_view text) : rest_(text) {}
  bool next(string_view& line) {
    while (!rest_.empty()) {
      const size_t end = std::min(rest_.find('\n'), rest_.size());
      line = rest_.substr(0, end);
      rest_.remove_prefix(std::min(end + 1, rest_.size()));
      ++number_;
      line = line.substr(0, line.find('#'));
      if (std::any_of(line.begin(), line.end(), [](char c) { return !is_space(c); })) return true;
    }
    return false;
  }
  long long number() const { return number_; }
  size_t remaining() const { return rest_.size(); }

 private:
  string_view rest_;
  long long number_ = 0;
};

bool parse_number(string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, error] = std::from_chars(token.data(), end, value);
  if (token.empty() || ptr != end) return false;
  // Overflow and underflow still have a value (inf or 0) that the callers judge.
  if (error == std::errc::result_out_of_range) value = std::strtod(std::string(token).c_str(), nullptr);
  return error == std::errc() || error == std::errc::result_out_of_range;
}

bool parse_integer(string_view token, long long& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, error] = std::from_chars(token.data(), end, value);
  return !token.empty() && error == std::errc() && ptr == end;
}

// Where in the file something is, formatted only when a message needs it.
struct Place {
  const char* what;  // "vertex", "face", "the face on line", ...
  long long number;
};
std::ostream& operator<<(std::ostream& out, const Place& place) {
  return out << place.what << ' ' << place.number;
}

// Collects vertices and fan-triangulated polygons, validating each as it arrives.
class MeshBuilder {
 public:
  // `index_base` is how the file writes its first vertex (OBJ: 1), for messages.
  MeshBuilder(const char* format, int index_base) : format_(format), index_base_(index_base) {}

  // Once the vertex count is known, indices are checked on arrival; otherwise in finish().
  void expect(long long vertices, long long polygons) {
    declared_vertices_ = vertices;
    mesh_.vertices.reserve(static_cast<size_t>(vertices));
    mesh_.faces.reserve(static_cast<size_t>(polygons));
  }
  long long vertex_count() const { return static_cast<long long>(mesh_.vertices.size()); }

  void add_vertex(double x, double y, double z, Place place) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      fail(format_, cat(place, " has a non-finite coordinate (", x, ", ", y, ", ", z, ")"));
    mesh_.vertices.emplace_back(x, y, z);
  }

  void require_corner_count(long long corners, Place place) const {
    if (corners < 3) fail(format_, cat(place, " has ", corners, " corners; a face needs at least 3"));
  }

  // `corners` are 0-based.
  void add_polygon(const std::vector<long long>& corners, Place place) {
    require_corner_count(static_cast<long long>(corners.size()), place);
    for (long long index : corners) {
      if (index < 0) fail(format_, cat(place, " refers to the negative vertex index ", index + index_base_));
      if (declared_vertices_ >= 0 && index >= declared_vertices_) out_of_range(place, index, declared_vertices_);
      if (index > INT_MAX)
        fail(format_, cat(place, " refers to vertex ", index + index_base_, ", which is out of range"));
      if (index > max_index_) max_index_ = index, max_index_place_ = place;
    }
    for (size_t k = 1; k + 1 < corners.size(); ++k)
      mesh_.faces.push_back({static_cast<int>(corners[0]), static_cast<int>(corners[k]),
                             static_cast<int>(corners[k + 1])});
    if (corners.size() > 3) ++split_polygons_;
  }

  LoadedMesh finish(std::string format_name) {
    if (mesh_.faces.empty()) fail(format_, "the file has no faces");
    if (max_index_ >= vertex_count()) out_of_range(max_index_place_, max_index_, vertex_count());
    LoadedMesh loaded{std::move(mesh_), std::move(format_name), {}};
    if (split_polygons_ > 0)
      loaded.notes.push_back(cat("split ", split_polygons_, split_polygons_ == 1 ? " polygon" : " polygons",
                                 " with more than three corners into triangles (fan triangulation)"));
    return loaded;
  }

 private:
  [[noreturn]] void out_of_range(Place place, long long index, long long vertices) const {
    fail(format_, cat(place, " refers to vertex ", index + index_base_, " but the file has ", vertices, " vertices"));
  }

  const char* format_;
  int index_base_;
  long long declared_vertices_ = -1;
  long long max_index_ = -1;
  Place max_index_place_{"face", 0};
  long long split_polygons_ = 0;
  TriangleMesh mesh_;
};

// ---------------------------------------------------------------------------------- OFF

// OFF, NOFF, COFF, CNOFF, STOFF...: optional letter prefixes before "OFF".
bool is_off_keyword(string_view word) {
  return word.size() >= 3 && word.substr(word.size() - 3) == "OFF" &&
         std::all_of(word.begin(), word.end() - 3, [](char c) { return c == 'C' || c == 'N' || c == 'S' || c == 'T'; });
}

LoadedMesh parse_off(string_view text) {
  constexpr const char* kFormat = "OFF";
  Lines lines(text);
  string_view line, token;
  if (!lines.next(line)) fail(kFormat, "the file is empty");
  Tokens header(line);
  header.next(token);
  if (!is_off_keyword(token))
    fail(kFormat, cat("expected an OFF header on line ", lines.number(), " but found ", shown(token)));

  // The counts usually sit on the next line but may follow the keyword directly.
  Tokens counts = header;
  if (string_view probe; !Tokens(header).next(probe)) {
    if (!lines.next(line)) fail(kFormat, "the file ends before the vertex and face counts");
    counts = Tokens(line);
  }
  long long num_vertices = 0, num_faces = 0;
  string_view vertex_token, face_token;
  counts.next(vertex_token);
  counts.next(face_token);
  if (vertex_token == "BINARY") fail(kFormat, "binary OFF files are not supported");
  if (!parse_integer(vertex_token, num_vertices) || !parse_integer(face_token, num_faces))
    fail(kFormat, cat("line ", lines.number(), " should hold the vertex and face counts but reads ", shown(line)));
  if (num_vertices < 0 || num_faces < 0)
    fail(kFormat, cat("negative counts in the header (", num_vertices, " vertices, ", num_faces, " faces)"));
  if (num_faces == 0) fail(kFormat, "the header declares no faces");
  // Shortest possible lines: "0 0 0\n" per vertex and "3 0 1 2" per face.
  const long long available = static_cast<long long>(lines.remaining());
  if (num_vertices > available / 6 || num_faces > available / 7 || 6 * num_vertices + 7 * num_faces > available)
    fail(kFormat, cat("the header declares ", num_vertices, " vertices and ", num_faces, " faces, but only ",
                      available, " bytes follow (truncated or corrupt?)"));

  MeshBuilder builder(kFormat, 0);
  builder.expect(num_vertices, num_faces);
  for (long long v = 0; v < num_vertices; ++v) {
    if (!lines.next(line))
      fail(kFormat, cat("the file ends after ", v, " of ", num_vertices, " vertices (truncated?)"));
    Tokens values(line);  // extra values (normals, colours) after x y z are ignored
    double xyz[3];
    for (double& coordinate : xyz)
      if (!values.next(token) || !parse_number(token, coordinate))
        fail(kFormat, cat("vertex ", v, " (line ", lines.number(), ") needs three numeric coordinates"));
    builder.add_vertex(xyz[0], xyz[1], xyz[2], {"vertex", v});
  }
  std::vector<long long> corners;
  for (long long f = 0; f < num_faces; ++f) {
    if (!lines.next(line)) fail(kFormat, cat("the file ends after ", f, " of ", num_faces, " faces (truncated?)"));
    Tokens values(line);
    long long count = 0;
    if (!values.next(token) || !parse_integer(token, count))
      fail(kFormat, cat("face ", f, " (line ", lines.number(), ") should start with its corner count, not ",
                        shown(token)));
    builder.require_corner_count(count, {"face", f});
    corners.clear();
    while (static_cast<long long>(corners.size()) < count) {  // grows only with tokens present
      long long index = 0;
      if (!values.next(token))
        fail(kFormat,
             cat("face ", f, " (line ", lines.number(), ") lists ", corners.size(), " of its ", count, " corners"));
      if (!parse_integer(token, index))
        fail(kFormat, cat("face ", f, " (line ", lines.number(), "): ", shown(token), " is not a vertex index"));
      corners.push_back(index);
    }
    builder.add_polygon(corners, {"face", f});
  }
  return builder.finish("off");
}

// ---------------------------------------------------------------------------------- OBJ

LoadedMesh parse_obj(string_view text) {
  constexpr const char* kFormat = "OBJ";
  MeshBuilder builder(kFormat, 1);
  Lines lines(text);
  string_view line, token;
  std::vector<long long> corners;
  while (lines.next(line)) {
    Tokens values(line);
    values.next(token);
    const long long line_number = lines.number();
    if (token == "v") {
      double xyz[3];
      for (double& coordinate : xyz)
        if (!values.next(token) || !parse_number(token, coordinate))
          fail(kFormat, cat("line ", line_number, ": a vertex needs three numeric coordinates"));
      builder.add_vertex(xyz[0], xyz[1], xyz[2], {"the vertex on line", line_number});
    } else if (token == "f") {
      corners.clear();
      while (values.next(token)) {
        // "a", "a/b", "a//c", "a/b/c": only the position index matters.
        long long index = 0;
        if (!parse_integer(token.substr(0, token.find('/')), index) || index == 0)
          fail(kFormat, cat("line ", line_number, ": ", shown(token), " is not a valid vertex reference"));
        if (index < 0) {  // relative to the vertices defined so far
          index += builder.vertex_count();
          if (index < 0)
            fail(kFormat,
                 cat("line ", line_number, ": relative index ", shown(token), " reaches before the first vertex"));
        } else {
          index -= 1;
        }
        corners.push_back(index);
      }
      builder.add_polygon(corners, {"the face on line", line_number});
    }
    // vt, vn, g, o, s, usemtl, mtllib, l, ... carry nothing the engine uses.
  }
  return builder.finish("obj");
}

// ---------------------------------------------------------------------------------- PLY

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
  std::vector<long long> corners;
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
          corners.clear();
          for (long long k = 0; k < count; ++k) corners.push_back(values.read_integer(property.type, "vertex index"));
          builder.add_polygon(corners, {"face", record});
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

// ---------------------------------------------------------------------------------- dispatch

enum class Format { Off, Obj, Ply, Unknown };

Format detect_format(string_view bytes, string_view name_hint) {
  if (bytes.substr(0, 4) == "ply\n" || bytes.substr(0, 4) == "ply\r") return Format::Ply;
  string_view first;
  Tokens(bytes).next(first);
  if (first.size() >= 3 && first.substr(first.size() - 3) == "OFF" &&
      std::all_of(first.begin(), first.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)); }))
    return Format::Off;
  const size_t dot = name_hint.rfind('.');
  std::string extension(dot == string_view::npos ? string_view() : name_hint.substr(dot + 1));
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == "off") return Format::Off;
  if (extension == "obj") return Format::Obj;
  if (extension == "ply") return Format::Ply;
  return Format::Unknown;
}

void append_le(std::string& out, const void* value, size_t size) {
  const char* bytes = static_cast<const char*>(value);
  if constexpr (std::endian::native == std::endian::little) {
    out.append(bytes, size);
  } else {
    for (size_t i = size; i-- > 0;) out += bytes[i];
  }
}

}  // namespace

LoadedMesh parse_mesh(const std::string& bytes, const std::string& name_hint) {
  string_view content = bytes;
  if (content.substr(0, 3) == "\xEF\xBB\xBF") content.remove_prefix(3);  // UTF-8 byte-order mark
  if (std::all_of(content.begin(), content.end(), is_space)) throw InputError("the mesh file is empty");
  switch (detect_format(content, name_hint)) {
    case Format::Off: return parse_off(content);
    case Format::Obj: return parse_obj(content);
    case Format::Ply: return parse_ply(content);
    case Format::Unknown: break;
  }
  throw InputError(cat("cannot tell the mesh format of ", name_hint.empty() ? "the data" : "'" + name_hint + "'",
                       ": expected an OFF, OBJ or PLY file (by content or extension)"));
}

LoadedMesh load_mesh(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw InputError(cat("cannot read mesh file '", path, "': it is a directory"));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(cat("cannot read mesh file '", path, "': ", std::strerror(errno)));
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) throw InputError(cat("cannot read mesh file '", path, "': read error"));
  try {
    return parse_mesh(contents.str(), path);
  } catch (const InputError& e) {
    throw InputError(cat(path, ": ", e.what()));
  }
}

void write_ply(const std::string& path, const TriangleMesh& mesh,
               const std::vector<std::array<unsigned char, 3>>& colours) {
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
