// Textured OBJ meshes and UV transfer from Python: isocorr.read_obj, write_obj and
// transfer_uvs, with the corner attributes as a dict of numpy arrays.
#pragma once

#include <pybind11/pybind11.h>

namespace isocorr::python {

namespace py = pybind11;

void register_texture(py::module_& module);

}  // namespace isocorr::python
