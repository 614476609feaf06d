// Precise maps and attribute transfer from Python: isocorr.precise_map and isocorr.transfer.
#pragma once

#include <pybind11/pybind11.h>

namespace isocorr::python {

namespace py = pybind11;

void register_transfer(py::module_& module);

}  // namespace isocorr::python
