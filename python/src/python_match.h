// isocorr.Shape (a preprocessed mesh, reusable across matches) and isocorr.match, which
// runs with the GIL released, ends on Ctrl-C (KeyboardInterrupt) and reports progress to an
// optional callback in the calling thread.
#pragma once

#include <pybind11/pybind11.h>

namespace isocorr::python {

namespace py = pybind11;

void register_match(py::module_& module);

}  // namespace isocorr::python
