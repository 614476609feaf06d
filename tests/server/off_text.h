// A mesh as ASCII OFF bytes, for the storage tests that upload meshes in process.
#pragma once

#include <sstream>
#include <string>

#include "isocorr/mesh/triangle_mesh.h"

namespace isocorr::server {

inline std::string off_text(const TriangleMesh& mesh) {
  std::ostringstream out;
  out.precision(17);
  out << "OFF\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n";
  for (const Vec3& p : mesh.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const Face& f : mesh.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return out.str();
}

}  // namespace isocorr::server
