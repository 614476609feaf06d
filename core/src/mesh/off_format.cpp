// OFF and its variants (NOFF, COFF, ...), ASCII only.
#include <algorithm>
#include <vector>

#include "mesh_builder.h"
#include "mesh_formats.h"
#include "text_scanning.h"

namespace isocorr::mesh_formats {
namespace {

// OFF, NOFF, COFF, CNOFF, STOFF...: optional letter prefixes before "OFF".
bool is_off_keyword(string_view word) {
  return word.size() >= 3 && word.substr(word.size() - 3) == "OFF" &&
         std::all_of(word.begin(), word.end() - 3, [](char c) { return c == 'C' || c == 'N' || c == 'S' || c == 'T'; });
}

}  // namespace

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
  builder.reserve_for_text(static_cast<size_t>(available));
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
  for (long long f = 0; f < num_faces; ++f) {
    if (!lines.next(line)) fail(kFormat, cat("the file ends after ", f, " of ", num_faces, " faces (truncated?)"));
    Tokens values(line);
    long long count = 0;
    if (!values.next(token) || !parse_integer(token, count))
      fail(kFormat, cat("face ", f, " (line ", lines.number(), ") should start with its corner count, not ",
                        shown(token)));
    builder.require_corner_count(count, {"face", f});
    builder.begin_polygon({"face", f});
    for (long long listed = 0; listed < count; ++listed) {
      long long index = 0;
      if (!values.next(token))
        fail(kFormat, cat("face ", f, " (line ", lines.number(), ") lists ", listed, " of its ", count, " corners"));
      if (!parse_integer(token, index))
        fail(kFormat, cat("face ", f, " (line ", lines.number(), "): ", shown(token), " is not a vertex index"));
      builder.add_corner(index);
    }
    builder.end_polygon();
  }
  return builder.finish("off");
}

std::string off_text(const TriangleMesh& mesh) {
  std::string out = cat("OFF\n", mesh.vertices.size(), " ", mesh.faces.size(), " 0\n");
  for (const Vec3& p : mesh.vertices) {
    for (int axis = 0; axis < 3; ++axis) {
      if (axis > 0) out += ' ';
      append_exact(out, p[axis]);
    }
    out += '\n';
  }
  for (const Face& face : mesh.faces) out += cat("3 ", face[0], " ", face[1], " ", face[2], "\n");
  return out;
}

}  // namespace isocorr::mesh_formats
