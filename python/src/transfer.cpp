#include "transfer.h"

#include <pybind11/numpy.h>

#include <algorithm>
#include <string>
#include <vector>

#include "isocorr/render/pair_picture.h"
#include "isocorr/render/png_file.h"
#include "isocorr/transfer/attribute_transfer.h"
#include "isocorr/transfer/precise_map.h"
#include "numpy_mesh.h"

namespace isocorr::python {
namespace {

using ValueArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A (V, F) pair or anything with V and F attributes (an isocorr.Shape).
TriangleMesh mesh_argument(const py::handle& argument, const char* name) {
  if (py::hasattr(argument, "V") && py::hasattr(argument, "F"))
    return mesh_from_arrays(argument.attr("V").cast<VertexArray>(), argument.attr("F").cast<FaceArray>());
  if (!py::isinstance<py::sequence>(argument) || py::len(argument) != 2)
    throw py::type_error(std::string(name) + " is an isocorr.Shape or a (V, F) pair of arrays");
  const auto pair = py::reinterpret_borrow<py::sequence>(argument);
  return mesh_from_arrays(pair[0].cast<VertexArray>(), pair[1].cast<FaceArray>());
}


py::tuple precise_map_py(const py::object& source, const py::object& target, const IndexArray& forward, int threads) {
  const TriangleMesh source_mesh = mesh_argument(source, "source"), target_mesh = mesh_argument(target, "target");
  const std::vector<int> map = index_vector(forward, "forward");
  PreciseMap points;
  {
    py::gil_scoped_release released;
    points = precise_map(source_mesh, target_mesh, map, threads);
  }
  return precise_arrays(points);
}

py::array transfer_py(const ValueArray& values, const py::object& map, const py::object& target_faces, bool labels) {
  if (values.ndim() != 1 && values.ndim() != 2) throw py::value_error("values are an array of shape (n,) or (n, k)");
  VertexTable table{static_cast<int>(values.shape(0)), values.ndim() == 2 ? static_cast<int>(values.shape(1)) : 1, {}};
  table.values.assign(values.data(), values.data() + values.size());
  const bool precise = py::isinstance<py::tuple>(map) || py::isinstance<py::list>(map);
  TriangleMesh target;
  PreciseMap points;
  std::vector<int> forward;
  if (precise) {
    if (target_faces.is_none()) throw py::value_error("a precise map needs the target's faces: transfer(values, (faces, weights), F)");
    const FaceArray faces = target_faces.cast<FaceArray>();
    // Only the faces take part: the positions are placeholders.
    VertexArray positions({static_cast<py::ssize_t>(table.rows), py::ssize_t{3}});
    std::fill(positions.mutable_data(), positions.mutable_data() + positions.size(), 0.0);
    target = mesh_from_arrays(positions, faces);
    points = precise_from_arrays(map.cast<py::sequence>());
  } else {
    forward = index_vector(map.cast<IndexArray>(), "map");
  }
  if (labels) {
    std::vector<int64_t> target_labels(table.values.begin(), table.values.end());
    if (table.columns != 1) throw py::value_error("labels are one value per vertex");
    for (size_t i = 0; i < target_labels.size(); ++i)
      if (static_cast<double>(target_labels[i]) != table.values[i])
        throw py::value_error("values[" + std::to_string(i) + "] is not a whole number, so no label");
    const std::vector<int64_t> out = precise ? pull_labels(target, target_labels, points) : pull_labels(target_labels, forward);
    return py::array_t<int64_t>(static_cast<py::ssize_t>(out.size()), out.data());
  }
  if (!precise && table.rows == 0) throw py::value_error("values hold no rows");
  const VertexTable out = precise ? pull_values(target, table, points) : pull_values(table, forward);
  if (values.ndim() == 1) return py::array_t<double>(static_cast<py::ssize_t>(out.rows), out.values.data());
  return py::array_t<double>({static_cast<py::ssize_t>(out.rows), static_cast<py::ssize_t>(out.columns)}, out.values.data());
}

void render_pair_py(const std::string& path, const py::object& source, const py::object& target,
                    const IndexArray& forward, int width, int height, const std::string& view) {
  const TriangleMesh source_mesh = mesh_argument(source, "source"), target_mesh = mesh_argument(target, "target");
  const std::vector<int> map = index_vector(forward, "forward");
  PairPictureOptions options;
  options.width = width;
  options.height = height;
  options.view = view;
  py::gil_scoped_release released;
  write_png(path, render_pair_picture(source_mesh, target_mesh, map, options));
}

}  // namespace

void register_transfer(py::module_& module) {
  module.def("render_pair", &render_pair_py, py::arg("path"), py::arg("source"), py::arg("target"), py::arg("forward"),
             py::arg("width") = 1200, py::arg("height") = 600, py::arg("view") = "principal",
             R"(Writes a PNG of source (left) and target (right), as `isocorr render` draws them.

The target is coloured by position and the source through forward, so a wrong or mirrored
map shows as colours in the wrong places. view: "principal" or a fixed side such as "+z".)");
  module.def("precise_map", &precise_map_py, py::arg("source"), py::arg("target"), py::arg("forward"),
             py::arg("threads") = 0,
             R"(The precise map of a vertex map: each source vertex's point on the target surface.

source and target are isocorr.Shape or (V, F) pairs; forward the target vertex of each
source vertex (-1: unmatched). Returns (faces, weights): int32 (n,) target face indices
(-1: unmatched) and float32 (n, 3) barycentric weights of each face's corners. Each point
carries the vertex's place among its neighbours onto the target by the least-squares
similarity of the neighbourhood and its images, projected onto the triangles around the image.)");
  module.def("transfer", &transfer_py, py::arg("values"), py::arg("map"), py::arg("F") = py::none(),
             py::arg("labels") = false,
             R"(Pulls per-vertex values of the target onto the source through a map.

values: (n_target,) or (n_target, k). map: the forward vertex map (int array), or a precise
map (faces, weights) from isocorr.precise_map, which then needs the target's faces F and
interpolates. Returns float64 of shape (n_source,) or (n_source, k), NaN where unmatched.
labels=True takes integer labels: the label of most weight at each point, never a blend,
int64, -1 where unmatched.)");
}

}  // namespace isocorr::python
