// Wavefront OBJ: vertex positions and faces, and when asked the corners' texture
// coordinates, normals and materials; everything else in the file is skipped.
#include <array>
#include <charconv>
#include <climits>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "mesh_builder.h"
#include "mesh_formats.h"
#include "text_scanning.h"

namespace isocorr::mesh_formats {

namespace {

constexpr const char* kFormat = "OBJ";

// An OBJ index as 0-based: 1-based, or negative counting back from the last of the
// `defined` elements so far. `token` is the whole corner, for the message.
long long resolve_index(string_view part, string_view token, long long defined, const char* what, long long line) {
  long long index = 0;
  if (!parse_integer(part, index) || index == 0)
    fail(kFormat, cat("line ", line, ": ", shown(token), " is not a valid ", what, " reference"));
  if (index > 0) return index - 1;
  index += defined;
  if (index < 0) fail(kFormat, cat("line ", line, ": relative index ", shown(token), " reaches before the first ", what));
  return index;
}

// The text after a line's keyword, trimmed: names may hold spaces.
string_view after_keyword(string_view line) {
  size_t begin = 0, end = line.size();
  while (begin < end && is_space(line[begin])) ++begin;
  while (begin < end && !is_space(line[begin])) ++begin;
  while (begin < end && is_space(line[begin])) ++begin;
  while (end > begin && is_space(line[end - 1])) --end;
  return line.substr(begin, end - begin);
}

// What a face corner refers to besides its vertex (-1: nothing).
struct CornerRefs {
  int uv = -1, normal = -1;
};

// One attribute list (vt or vn) and the largest forward reference into it, checked once
// the whole file is read, as MeshBuilder checks vertex indices.
struct ReferencedList {
  const char* what;
  long long max_index = -1, max_line = 0;

  int reference(string_view part, string_view token, long long defined, long long line) {
    const long long index = resolve_index(part, token, defined, what, line);
    if (index > INT_MAX) fail(kFormat, cat("line ", line, ": ", shown(token), " refers to a ", what, " out of range"));
    if (index > max_index) max_index = index, max_line = line;
    return static_cast<int>(index);
  }
  void check(long long defined) const {
    if (max_index >= defined)
      fail(kFormat, cat("the face on line ", max_line, " refers to ", what, " ", max_index + 1, " but the file has ",
                        defined));
  }
};

// Collects the corner attributes beside MeshBuilder: the vt and vn lists, each kept fan
// triangle's corner references, and the material in effect.
class CornerRecorder {
 public:
  explicit CornerRecorder(CornerAttributes& out) : out_(out) {}

  void add_uv(Tokens& values, long long line) {
    // "vt u [v [w]]": v defaults to 0, w (3D textures) is dropped.
    std::array<double, 2> uv{0, 0};
    string_view token;
    int count = 0;
    bool numbers = true;
    for (; count < 2 && values.next(token); ++count)
      numbers = numbers && parse_number(token, uv[count]) && std::isfinite(uv[count]);
    if (count == 0 || !numbers) fail(kFormat, cat("line ", line, ": a texture coordinate needs one or two finite numbers"));
    out_.uvs.push_back(uv);
  }
  void add_normal(Tokens& values, long long line) {
    double xyz[3];
    string_view token;
    for (double& coordinate : xyz)
      if (!values.next(token) || !parse_number(token, coordinate) || !std::isfinite(coordinate))
        fail(kFormat, cat("line ", line, ": a normal needs three finite numbers"));
    out_.normals.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  void use_material(string_view name) {
    material_ = name;
    material_index_ = kNotLookedUp;
  }
  void add_library(string_view names) {
    if (names.empty() || out_.material_library == names) return;
    if (!out_.material_library.empty()) out_.material_library += ' ';  // mtllib takes several names
    out_.material_library += names;
  }

  // The references after a corner's vertex index: "v", "v/t", "v//n" or "v/t/n".
  CornerRefs corner(string_view token, long long line) {
    CornerRefs refs;
    const size_t slash = token.find('/');
    if (slash == string_view::npos) return refs;
    const string_view rest = token.substr(slash + 1);
    const size_t second = rest.find('/');
    const string_view uv = rest.substr(0, second);
    const string_view normal = second == string_view::npos ? string_view() : rest.substr(second + 1);
    if ((second == string_view::npos ? uv.empty() : normal.empty()) || normal.find('/') != string_view::npos)
      fail(kFormat, cat("line ", line, ": ", shown(token), " is not a corner of the form v, v/vt, v//vn or v/vt/vn"));
    if (!uv.empty()) refs.uv = uv_refs_.reference(uv, token, static_cast<long long>(out_.uvs.size()), line);
    if (!normal.empty())
      refs.normal = normal_refs_.reference(normal, token, static_cast<long long>(out_.normals.size()), line);
    return refs;
  }

  // Face `face` is the fan triangle of corners a, b, c.
  void add_triangle(size_t face, const CornerRefs& a, const CornerRefs& b, const CornerRefs& c) {
    put(out_.face_uvs, {a.uv, b.uv, c.uv}, {-1, -1, -1}, face);
    put(out_.face_normals, {a.normal, b.normal, c.normal}, {-1, -1, -1}, face);
    if (material_index_ == kNotLookedUp) material_index_ = material_number();
    put(out_.face_materials, material_index_, -1, face);
  }

  void finish() const {
    uv_refs_.check(static_cast<long long>(out_.uvs.size()));
    normal_refs_.check(static_cast<long long>(out_.normals.size()));
  }

 private:
  static constexpr int kNotLookedUp = -2;

  // A per-face list stays empty until a face has the attribute, then holds every face.
  template <class T>
  static void put(std::vector<T>& list, const T& value, const T& none, size_t face) {
    if (list.empty() && value == none) return;
    list.resize(face, none);
    list.push_back(value);
  }
  // Materials are numbered when a face first uses them, so that unused usemtl lines leave
  // no trace and a written file reads back with the same numbers.
  int material_number() {
    if (material_.empty()) return -1;
    const auto [it, added] = material_numbers_.try_emplace(material_, static_cast<int>(out_.materials.size()));
    if (added) out_.materials.emplace_back(material_);
    return it->second;
  }

  CornerAttributes& out_;
  ReferencedList uv_refs_{"texture coordinate"}, normal_refs_{"normal"};
  string_view material_;  // views into the file's bytes, which outlive the reader
  int material_index_ = -1;
  std::unordered_map<string_view, int> material_numbers_;
};

}  // namespace

LoadedMesh parse_obj(string_view text, CornerAttributes* corners) {
  MeshBuilder builder(kFormat, 1);
  builder.reserve_for_text(text.size());
  std::optional<CornerRecorder> recorder;
  if (corners) {
    *corners = CornerAttributes{};
    recorder.emplace(*corners);
  }
  Lines lines(text);
  string_view line, token;
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
      builder.begin_polygon({"the face on line", line_number});
      CornerRefs first, previous;
      for (long long corner = 0; values.next(token); ++corner) {
        // Without a recorder only the position index is read, as matching always has.
        const long long index =
            resolve_index(token.substr(0, token.find('/')), token, builder.vertex_count(), "vertex", line_number);
        const CornerRefs refs = recorder ? recorder->corner(token, line_number) : CornerRefs{};
        const size_t faces = builder.face_count();
        builder.add_corner(index);
        if (recorder && builder.face_count() > faces) recorder->add_triangle(faces, first, previous, refs);
        if (corner == 0) first = refs;
        previous = refs;
      }
      builder.end_polygon();
    } else if (recorder && token == "vt") {
      recorder->add_uv(values, line_number);
    } else if (recorder && token == "vn") {
      recorder->add_normal(values, line_number);
    } else if (recorder && token == "usemtl") {
      recorder->use_material(after_keyword(line));
    } else if (recorder && token == "mtllib") {
      recorder->add_library(after_keyword(line));
    }
    // g, o, s, l, ... carry nothing the engine uses.
  }
  LoadedMesh loaded = builder.finish("obj");
  if (recorder) recorder->finish();
  return loaded;
}

std::string obj_text(const TriangleMesh& mesh, const CornerAttributes& corners) {
  std::string out = "# written by isocorr\n";
  if (!corners.material_library.empty()) out += cat("mtllib ", corners.material_library, "\n");
  const auto append_line = [&out](const char* keyword, const auto& values, int count) {
    out += keyword;
    for (int axis = 0; axis < count; ++axis) {
      out += ' ';
      append_exact(out, values[axis]);
    }
    out += '\n';
  };
  for (const Vec3& p : mesh.vertices) append_line("v", p, 3);
  for (const auto& uv : corners.uvs) append_line("vt", uv, 2);
  for (const Vec3& n : corners.normals) append_line("vn", n, 3);
  const auto append_index = [&out](int index) {
    char digits[16];
    out.append(digits, std::to_chars(digits, digits + sizeof digits, index + 1).ptr);  // OBJ counts from 1
  };
  int material = -1;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (!corners.face_materials.empty() && corners.face_materials[f] != material) {
      material = corners.face_materials[f];
      out += material < 0 ? std::string("usemtl\n") : cat("usemtl ", corners.materials[material], "\n");
    }
    out += 'f';
    for (int k = 0; k < 3; ++k) {
      const int uv = corners.face_uvs.empty() ? -1 : corners.face_uvs[f][k];
      const int normal = corners.face_normals.empty() ? -1 : corners.face_normals[f][k];
      out += ' ';
      append_index(mesh.faces[f][k]);
      if (uv >= 0 || normal >= 0) out += '/';
      if (uv >= 0) append_index(uv);
      if (normal >= 0) out += '/', append_index(normal);
    }
    out += '\n';
  }
  return out;
}

std::string obj_text(const TriangleMesh& mesh) { return obj_text(mesh, CornerAttributes{}); }

}  // namespace isocorr::mesh_formats
