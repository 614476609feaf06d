// Format detection and dispatch to the readers of off_format.cpp, obj_format.cpp and
// ply_format.cpp, and reading mesh files from disk.
#include "isocorr/mesh/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include "isocorr/util/error.h"
#include "mesh_formats.h"
#include "text_scanning.h"

namespace isocorr {

namespace {

using mesh_formats::cat;
using mesh_formats::is_space;
using mesh_formats::Tokens;
using std::string_view;

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

}  // namespace

namespace mesh_formats {

LoadedMesh parse_mesh_bytes(const std::string& bytes, const std::string& name_hint, CornerAttributes* corners) {
  string_view content = bytes;
  if (content.substr(0, 3) == "\xEF\xBB\xBF") content.remove_prefix(3);  // UTF-8 byte-order mark
  if (std::all_of(content.begin(), content.end(), is_space)) throw InputError("the mesh file is empty");
  switch (detect_format(content, name_hint)) {
    case Format::Off: return parse_off(content);
    case Format::Obj: return parse_obj(content, corners);
    case Format::Ply: return parse_ply(content);
    case Format::Unknown: break;
  }
  throw InputError(cat("cannot tell the mesh format of ", name_hint.empty() ? "the data" : "'" + name_hint + "'",
                       ": expected an OFF, OBJ or PLY file (by content or extension)"));
}

LoadedMesh load_mesh_file(const std::string& path, CornerAttributes* corners) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
    throw InputError(cat("cannot read mesh file '", path, "': it is a directory"));
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(cat("cannot read mesh file '", path, "': ", std::strerror(errno)));
  // Read straight into one buffer of the file's size: the bytes are held once while parsing.
  std::string contents(static_cast<size_t>(std::max<std::streamoff>(in.tellg(), 0)), '\0');
  in.seekg(0);
  in.read(contents.data(), static_cast<std::streamsize>(contents.size()));
  if (in.bad() || static_cast<size_t>(in.gcount()) != contents.size())
    throw InputError(cat("cannot read mesh file '", path, "': read error"));
  try {
    return parse_mesh_bytes(contents, path, corners);
  } catch (const InputError& e) {
    throw InputError(cat(path, ": ", e.what()));
  }
}

void write_text_file(const std::string& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(text.data(), static_cast<std::streamsize>(text.size()));
  file.close();
  if (!file) throw InputError(cat("cannot write mesh file '", path, "'"));
}

}  // namespace mesh_formats

LoadedMesh parse_mesh(const std::string& bytes, const std::string& name_hint) {
  return mesh_formats::parse_mesh_bytes(bytes, name_hint, nullptr);
}

LoadedMesh load_mesh(const std::string& path) { return mesh_formats::load_mesh_file(path, nullptr); }

void write_mesh(const std::string& path, const TriangleMesh& mesh) {
  const std::string extension = std::filesystem::path(path).extension().string();
  std::string lower(extension);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  if (lower == ".ply") return write_ply(path, mesh);
  if (lower != ".off" && lower != ".obj")
    throw InputError(cat("cannot write mesh file '", path, "': its name must end in .off, .obj or .ply"));
  mesh_formats::write_text_file(path, lower == ".off" ? mesh_formats::off_text(mesh) : mesh_formats::obj_text(mesh));
}

}  // namespace isocorr
