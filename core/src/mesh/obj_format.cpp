// Wavefront OBJ: vertex positions and faces; everything else in the file is skipped.
#include "mesh_builder.h"
#include "mesh_formats.h"
#include "text_scanning.h"

namespace isocorr::mesh_formats {

LoadedMesh parse_obj(string_view text) {
  constexpr const char* kFormat = "OBJ";
  MeshBuilder builder(kFormat, 1);
  builder.reserve_for_text(text.size());
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
        builder.add_corner(index);
      }
      builder.end_polygon();
    }
    // vt, vn, g, o, s, usemtl, mtllib, l, ... carry nothing the engine uses.
  }
  return builder.finish("obj");
}

std::string obj_text(const TriangleMesh& mesh) {
  std::string out = "# written by isocorr\n";
  for (const Vec3& p : mesh.vertices) {
    out += 'v';
    for (int axis = 0; axis < 3; ++axis) {
      out += ' ';
      append_exact(out, p[axis]);
    }
    out += '\n';
  }
  // OBJ numbers vertices from 1.
  for (const Face& face : mesh.faces) out += cat("f ", face[0] + 1, " ", face[1] + 1, " ", face[2] + 1, "\n");
  return out;
}

}  // namespace isocorr::mesh_formats
