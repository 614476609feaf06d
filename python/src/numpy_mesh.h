// Meshes as numpy arrays: V (#V x 3 float64) and F (#F x 3 int32), the layout of libigl,
// potpourri3d and trimesh.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "isocorr/mesh/triangle_mesh.h"
#include "isocorr/transfer/surface_point.h"

namespace isocorr::python {

namespace py = pybind11;

using VertexArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using FaceArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

// The mesh of V and F; raises ValueError naming the array and what is wrong with it (its
// shape, a non-finite coordinate, an index outside V).
TriangleMesh mesh_from_arrays(const VertexArray& vertices, const FaceArray& faces);
// (V, F) of a mesh.
py::tuple arrays_from_mesh(const TriangleMesh& mesh);
// The entries of a 1-D array of vertex indices (-1 allowed); raises ValueError naming
// `name` and the first entry that is no index.
std::vector<int> index_vector(const IndexArray& array, const std::string& name);
// A 1-D int32 or float32 array holding a copy of `values`.
py::array_t<int32_t> int_array(const std::vector<int>& values);
py::array_t<float> float_array(const std::vector<float>& values);

// (faces, weights): int32 (n,) and float32 (n, 3) copies of a precise map's points.
py::tuple precise_arrays(const PreciseMap& points);

// A precise map from a (faces, weights) pair of arrays; raises ValueError for other shapes.
PreciseMap precise_from_arrays(const py::sequence& pair);

// read_mesh and write_mesh.
void register_mesh_functions(py::module_& module);

}  // namespace isocorr::python
