// isocorr._isocorr: the engine for Python. isocorr/__init__.py re-exports it.
#include <pybind11/pybind11.h>

#include "isocorr/util/error.h"
#include "isocorr/version.h"
#include "evaluation.h"
#include "numpy_mesh.h"
#include "python_match.h"
#include "settings_kwargs.h"
#include "texture.h"
#include "transfer.h"

namespace py = pybind11;

PYBIND11_MODULE(_isocorr, module) {
  module.doc() = "Dense correspondence between nearly isometric triangle meshes (isocorr's engine).";
  module.attr("__version__") = isocorr::kVersion;
  // The engine's refusals of input are the caller's mistake: ValueError, with its message.
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const isocorr::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  isocorr::python::register_mesh_functions(module);
  isocorr::python::register_settings_functions(module);
  isocorr::python::register_match(module);
  isocorr::python::register_evaluation(module);
  isocorr::python::register_transfer(module);
  isocorr::python::register_texture(module);
}
