// Scoring a map against ground truth from Python, as `isocorr eval` does: geodesic error,
// the Kim et al. curve and its AUC, flips, and SHREC'20 coverage.
#pragma once

#include <pybind11/pybind11.h>

namespace isocorr::python {

namespace py = pybind11;

// isocorr.evaluate and isocorr.coverage.
void register_evaluation(py::module_& module);

}  // namespace isocorr::python
