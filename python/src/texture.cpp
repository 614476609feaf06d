#include "texture.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "isocorr/mesh/textured_mesh.h"
#include "isocorr/transfer/precise_map.h"
#include "isocorr/transfer/uv_transfer.h"
#include "numpy_mesh.h"

namespace isocorr::python {
namespace {

using CornerArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;
using RowArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

template <class Row>
py::array_t<typename Row::value_type> rows_array(const std::vector<Row>& rows, py::ssize_t width) {
  py::array_t<typename Row::value_type> array({static_cast<py::ssize_t>(rows.size()), width});
  auto out = array.template mutable_unchecked<2>();
  for (size_t r = 0; r < rows.size(); ++r)
    for (py::ssize_t c = 0; c < width; ++c) out(r, c) = rows[r][c];
  return array;
}

// Rows of a (n, width) array; raises ValueError naming `key` for another shape.
template <class Row, class Array>
std::vector<Row> array_rows(const py::dict& mesh, const char* key, py::ssize_t width) {
  std::vector<Row> rows;
  if (!mesh.contains(key) || mesh[key].is_none()) return rows;
  const Array array = mesh[key].cast<Array>();
  if (array.ndim() != 2 || array.shape(1) != width)
    throw py::value_error(std::string(key) + " must be an array of shape (n, " + std::to_string(width) + ")");
  const auto in = array.template unchecked<2>();
  rows.resize(array.shape(0));
  for (py::ssize_t r = 0; r < array.shape(0); ++r)
    for (py::ssize_t c = 0; c < width; ++c) rows[r][c] = static_cast<typename Row::value_type>(in(r, c));
  return rows;
}

py::dict corners_dict(const TriangleMesh& mesh, const CornerAttributes& corners) {
  py::dict out;
  const py::tuple arrays = arrays_from_mesh(mesh);
  out["V"] = arrays[0];
  out["F"] = arrays[1];
  out["uv"] = rows_array(corners.uvs, 2);
  out["face_uv"] = rows_array(corners.face_uvs, 3);
  std::vector<std::array<double, 3>> normals(corners.normals.size());
  for (size_t i = 0; i < normals.size(); ++i) normals[i] = {corners.normals[i].x(), corners.normals[i].y(), corners.normals[i].z()};
  out["normals"] = rows_array(normals, 3);
  out["face_normals"] = rows_array(corners.face_normals, 3);
  out["material_library"] = corners.material_library;
  out["materials"] = corners.materials;
  out["face_materials"] = py::array_t<int>(static_cast<py::ssize_t>(corners.face_materials.size()), corners.face_materials.data());
  return out;
}

TexturedMesh textured_from_dict(const py::dict& mesh) {
  if (!mesh.contains("V") || !mesh.contains("F")) throw py::value_error("a textured mesh is a dict with V and F");
  TexturedMesh textured{mesh_from_arrays(mesh["V"].cast<VertexArray>(), mesh["F"].cast<FaceArray>()), {}};
  CornerAttributes& c = textured.corners;
  c.uvs = array_rows<std::array<double, 2>, RowArray>(mesh, "uv", 2);
  c.face_uvs = array_rows<std::array<int, 3>, CornerArray>(mesh, "face_uv", 3);
  for (const auto& n : array_rows<std::array<double, 3>, RowArray>(mesh, "normals", 3)) c.normals.emplace_back(n[0], n[1], n[2]);
  c.face_normals = array_rows<std::array<int, 3>, CornerArray>(mesh, "face_normals", 3);
  if (mesh.contains("material_library")) c.material_library = mesh["material_library"].cast<std::string>();
  if (mesh.contains("materials")) c.materials = mesh["materials"].cast<std::vector<std::string>>();
  if (mesh.contains("face_materials")) c.face_materials = mesh["face_materials"].cast<std::vector<int>>();
  check_corner_attributes(textured.mesh, c);
  return textured;
}

py::dict transfer_uvs_py(const py::object& source, const py::dict& target, const py::object& map) {
  const TexturedMesh target_mesh = textured_from_dict(target);
  TriangleMesh source_mesh;
  if (py::isinstance<py::dict>(source)) {
    source_mesh = textured_from_dict(source.cast<py::dict>()).mesh;
  } else {
    const auto pair = source.cast<py::sequence>();
    source_mesh = mesh_from_arrays(pair[0].cast<VertexArray>(), pair[1].cast<FaceArray>());
  }
  PreciseMap points;
  if (py::isinstance<py::tuple>(map) || py::isinstance<py::list>(map)) {
    points = precise_from_arrays(map.cast<py::sequence>());
  } else {
    points = precise_map(source_mesh, target_mesh.mesh, index_vector(map.cast<IndexArray>(), "map"));
  }
  CornerAttributes corners;
  {
    py::gil_scoped_release released;
    corners = transfer_uvs(source_mesh, target_mesh, points);
  }
  return corners_dict(source_mesh, corners);
}

}  // namespace

void register_texture(py::module_& module) {
  module.def(
      "read_obj", [](const std::string& path) {
        const TexturedMesh textured = load_textured_mesh(path);
        return corners_dict(textured.mesh, textured.corners);
      },
      py::arg("path"),
      R"(Reads an OBJ with its corner attributes, as a dict: V, F (as read_mesh gives them), uv
(k, 2), face_uv (m, 3) indices into uv per triangle corner (seams keep their own UVs),
normals and face_normals likewise, material_library, materials (names) and face_materials
(m,) indices into them (-1: none). Empty arrays where the file has no such attribute.)");
  module.def(
      "write_obj", [](const std::string& path, const py::dict& mesh) { write_textured_obj(path, textured_from_dict(mesh)); },
      py::arg("path"), py::arg("mesh"), "Writes a dict as read_obj gives it (V and F required) as an OBJ file.");
  module.def("transfer_uvs", &transfer_uvs_py, py::arg("source"), py::arg("target"), py::arg("map"),
             R"(Gives the source the texture coordinates and materials of a textured target.

source: a (V, F) pair or a read_obj dict; target: a read_obj dict with uv; map: the forward
vertex map (a precise map is made from it) or a precise map (faces, weights). Returns a
dict as read_obj gives it for the source (write it with write_obj): each corner's UV is
interpolated at its vertex's point, and a triangle whose corners land on different UV
islands takes all three from one (see uv_transfer.h).)");
}

}  // namespace isocorr::python
