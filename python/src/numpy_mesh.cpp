#include "numpy_mesh.h"

#include <algorithm>
#include <limits>
#include <string>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/output/attribute_files.h"

namespace isocorr::python {
namespace {

// "(n, 3)", as numpy prints a shape.
std::string shape_of(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d) text += (d ? ", " : "") + std::to_string(array.shape(d));
  return text + (array.ndim() == 1 ? ",)" : ")");
}

}  // namespace

TriangleMesh mesh_from_arrays(const VertexArray& vertices, const FaceArray& faces) {
  if (vertices.ndim() != 2 || vertices.shape(1) != 3)
    throw py::value_error("V must be an array of shape (n, 3), got shape " + shape_of(vertices));
  if (faces.ndim() != 2 || faces.shape(1) != 3)
    throw py::value_error("F must be an array of shape (m, 3) of vertex indices, got shape " + shape_of(faces));
  TriangleMesh mesh;
  const auto v = vertices.unchecked<2>();
  mesh.vertices.resize(v.shape(0));
  for (py::ssize_t i = 0; i < v.shape(0); ++i) {
    mesh.vertices[i] = Vec3(v(i, 0), v(i, 1), v(i, 2));
    if (!mesh.vertices[i].allFinite())
      throw py::value_error("V: vertex " + std::to_string(i) + " has a coordinate that is not finite");
  }
  const auto f = faces.unchecked<2>();
  mesh.faces.resize(f.shape(0));
  for (py::ssize_t i = 0; i < f.shape(0); ++i)
    for (int corner = 0; corner < 3; ++corner) {
      const int64_t index = f(i, corner);
      if (index < 0 || index >= v.shape(0))
        throw py::value_error("F: face " + std::to_string(i) + " names vertex " + std::to_string(index) +
                              ", outside V's " + std::to_string(v.shape(0)) + " vertices");
      mesh.faces[i][corner] = static_cast<int>(index);
    }
  return mesh;
}

py::tuple arrays_from_mesh(const TriangleMesh& mesh) {
  py::array_t<double> vertices({static_cast<py::ssize_t>(mesh.vertices.size()), py::ssize_t{3}});
  auto v = vertices.mutable_unchecked<2>();
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int axis = 0; axis < 3; ++axis) v(i, axis) = mesh.vertices[i][axis];
  py::array_t<int32_t> faces({static_cast<py::ssize_t>(mesh.faces.size()), py::ssize_t{3}});
  auto f = faces.mutable_unchecked<2>();
  for (size_t i = 0; i < mesh.faces.size(); ++i)
    for (int corner = 0; corner < 3; ++corner) f(i, corner) = mesh.faces[i][corner];
  return py::make_tuple(vertices, faces);
}

py::array_t<int32_t> int_array(const std::vector<int>& values) {
  py::array_t<int32_t> array(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), array.mutable_data());
  return array;
}

std::vector<int> index_vector(const IndexArray& array, const std::string& name) {
  if (array.ndim() != 1) throw py::value_error(name + " must be a one-dimensional array of vertex indices");
  const auto values = array.unchecked<1>();
  std::vector<int> out(values.shape(0));
  for (py::ssize_t i = 0; i < values.shape(0); ++i) {
    if (values(i) < -1 || values(i) > std::numeric_limits<int>::max())
      throw py::value_error(name + "[" + std::to_string(i) + "] = " + std::to_string(values(i)) +
                            " is no vertex index (nor -1)");
    out[i] = static_cast<int>(values(i));
  }
  return out;
}

py::array_t<float> float_array(const std::vector<float>& values) {
  py::array_t<float> array(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), array.mutable_data());
  return array;
}

py::tuple precise_arrays(const PreciseMap& points) {
  py::array_t<int32_t> faces(static_cast<py::ssize_t>(points.size()));
  py::array_t<float> weights({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto f = faces.mutable_unchecked<1>();
  auto w = weights.mutable_unchecked<2>();
  for (size_t v = 0; v < points.size(); ++v) {
    f(v) = points[v].face;
    for (int j = 0; j < 3; ++j) w(v, j) = points[v].weights[j];
  }
  return py::make_tuple(faces, weights);
}

PreciseMap precise_from_arrays(const py::sequence& pair) {
  if (py::len(pair) != 2) throw py::value_error("a precise map is a (faces, weights) pair of arrays");
  const std::vector<int> faces = index_vector(pair[0].cast<IndexArray>(), "faces");
  const py::array_t<float, py::array::c_style | py::array::forcecast> weights = pair[1].cast<py::array_t<float, py::array::c_style | py::array::forcecast>>();
  if (weights.ndim() != 2 || weights.shape(1) != 3 || static_cast<size_t>(weights.shape(0)) != faces.size())
    throw py::value_error("the weights of a precise map are a float array of shape (len(faces), 3)");
  const auto w = weights.unchecked<2>();
  PreciseMap map(faces.size());
  for (size_t v = 0; v < faces.size(); ++v) map[v] = {faces[v], {w(v, 0), w(v, 1), w(v, 2)}};
  return map;
}

void register_mesh_functions(py::module_& module) {
  module.def(
      "read_mesh", [](const std::string& path) { return arrays_from_mesh(load_mesh(path).mesh); }, py::arg("path"),
      R"(Reads an OFF, OBJ or PLY mesh file.

Returns (V, F): V the vertex positions, float64 of shape (n, 3); F the triangles, int32 of
shape (m, 3), 0-based. Polygons are split into triangles. Raises ValueError naming what is
wrong with a malformed file.)");
  module.def(
      "write_mesh",
      [](const std::string& path, const VertexArray& vertices, const FaceArray& faces, const py::object& colors) {
        const TriangleMesh mesh = mesh_from_arrays(vertices, faces);
        if (colors.is_none()) return write_mesh(path, mesh);
        if (!path.ends_with(".ply")) throw py::value_error("vertex colours are written to PLY files only: " + path);
        const auto table = colors.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
        if (table.ndim() != 2 || table.shape(1) != 3) throw py::value_error("colors must be an array of shape (n, 3)");
        write_coloured_ply(path, mesh, {static_cast<int>(table.shape(0)), 3, {table.data(), table.data() + table.size()}});
      },
      py::arg("path"), py::arg("V"), py::arg("F"), py::arg("colors") = py::none(),
      R"(Writes V (n, 3) and F (m, 3) to `path`: OFF or OBJ with exact coordinates, or binary
PLY (float coordinates), by the name's extension. colors (n, 3), PLY only: per-vertex RGB,
floats in [0, 1] or integers in [0, 255]; NaN (an unmatched vertex) is grey.)");
}

}  // namespace isocorr::python
