#include "python_match.h"

#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <deque>
#include <exception>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "isocorr/pipeline/run_match.h"
#include "isocorr/shape/preprocessed_shape.h"
#include "numpy_mesh.h"
#include "settings_kwargs.h"

namespace isocorr::python {
namespace {

// How often the waiting Python thread looks for Ctrl-C and hands on progress.
constexpr std::chrono::milliseconds kPollInterval(50);

// A mesh preprocessed once (the engine's per-mesh work: cleaning, geodesics, samples, the
// spectral basis), for any number of matches under the same preprocessing settings.
struct Shape {
  TriangleMesh mesh;
  std::shared_ptr<const PreprocessedShape> shape;
};

// The result as Python sees it: copies of the maps as numpy arrays are made on access.
struct Match {
  MatchResult result;
};

// Runs `work` on its own thread while this one, holding the GIL only between waits,
// checks for signals (Ctrl-C raises KeyboardInterrupt and cancels the work) and calls
// `progress` with what the work reported. Rethrows the work's exception.
template <class Result>
Result run_interruptibly(const std::function<Result(const JobControl&)>& work, const py::object& progress) {
  std::atomic<bool> cancel{false};
  std::mutex mutex;
  std::deque<Progress> reported;
  JobControl control;
  control.cancel_requested = &cancel;
  if (!progress.is_none())
    control.on_progress = [&](const Progress& p) {
      const std::lock_guard<std::mutex> lock(mutex);
      reported.push_back(p);
    };
  std::future<Result> running = std::async(std::launch::async, [&] { return work(control); });
  auto deliver = [&] {
    std::deque<Progress> batch;
    {
      const std::lock_guard<std::mutex> lock(mutex);
      batch.swap(reported);
    }
    for (const Progress& p : batch) progress(p.stage, p.fraction);
  };
  for (;;) {
    bool done = false;
    {
      py::gil_scoped_release released;
      done = running.wait_for(kPollInterval) == std::future_status::ready;
    }
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!progress.is_none()) deliver();
    } catch (...) {
      // Ctrl-C, or the callback raised: the work ends at its next safe point first.
      cancel = true;
      {
        py::gil_scoped_release released;
        running.wait();
      }
      throw;
    }
    if (done) break;
  }
  return running.get();
}

// A row-major float32 (rows x cols) copy of an Eigen matrix.
template <class Matrix>
py::array_t<float> matrix_array(const Matrix& matrix) {
  py::array_t<float> array({static_cast<py::ssize_t>(matrix.rows()), static_cast<py::ssize_t>(matrix.cols())});
  auto out = array.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < matrix.rows(); ++i)
    for (Eigen::Index j = 0; j < matrix.cols(); ++j) out(i, j) = matrix(i, j);
  return array;
}

// The shape's spectral basis with one row per vertex given (a merged duplicate shares its
// representative's row).
py::array_t<float> basis_in_input_numbering(const PreprocessedShape& shape) {
  const PreprocessedShape::SpectralBasis& basis = shape.spectral_basis();
  const std::vector<int>& input_to_clean = shape.clean().input_to_clean;
  py::array_t<float> array({static_cast<py::ssize_t>(input_to_clean.size()), static_cast<py::ssize_t>(basis.cols())});
  auto out = array.mutable_unchecked<2>();
  for (size_t i = 0; i < input_to_clean.size(); ++i)
    for (Eigen::Index j = 0; j < basis.cols(); ++j) out(i, j) = basis(input_to_clean[i], j);
  return array;
}

// Hands run_match the shapes the caller built.
class GivenShapes : public ShapeProvider {
 public:
  GivenShapes(std::shared_ptr<const PreprocessedShape> source, std::shared_ptr<const PreprocessedShape> target)
      : source_(std::move(source)), target_(std::move(target)) {}
  std::shared_ptr<const PreprocessedShape> shape(ShapeRole role, const PreprocessOptions&, const JobControl&) override {
    return role == ShapeRole::kSource ? source_ : target_;
  }

 private:
  std::shared_ptr<const PreprocessedShape> source_, target_;
};

// A match argument: a Shape, or (V, F).
std::optional<Shape> shape_argument(const py::handle& argument) {
  if (py::isinstance<Shape>(argument)) return std::nullopt;
  if (!py::isinstance<py::sequence>(argument) || py::len(argument) != 2)
    throw py::type_error("source and target are each an isocorr.Shape or a (V, F) pair of arrays");
  const py::sequence pair = py::reinterpret_borrow<py::sequence>(argument);
  return Shape{mesh_from_arrays(pair[0].cast<VertexArray>(), pair[1].cast<FaceArray>()), nullptr};
}

Match match(const py::object& source, const py::object& target, const py::object& progress,
            const py::kwargs& kwargs) {
  std::optional<Shape> source_mesh = shape_argument(source), target_mesh = shape_argument(target);
  const bool given_shapes = !source_mesh && !target_mesh;
  if (static_cast<bool>(source_mesh) != static_cast<bool>(target_mesh))
    throw py::type_error("give two isocorr.Shape or two (V, F) pairs, not one of each");
  MatchSettings settings;
  std::vector<SettingScope> allowed = {SettingScope::kMatch, SettingScope::kLocal};
  if (!given_shapes) allowed.push_back(SettingScope::kPreprocess);
  apply_settings(kwargs, allowed, settings);
  if (given_shapes) {
    const Shape& s = source.cast<const Shape&>();
    const Shape& t = target.cast<const Shape&>();
    if (s.shape->options().key() != t.shape->options().key())
      throw py::value_error("the two shapes were preprocessed with different settings");
    settings.preprocess = s.shape->options();
    GivenShapes shapes(s.shape, t.shape);
    return Match{run_interruptibly<MatchResult>(
        [&](const JobControl& control) { return run_match(shapes, settings, control); }, progress)};
  }
  return Match{run_interruptibly<MatchResult>(
      [&](const JobControl& control) { return match_meshes(source_mesh->mesh, target_mesh->mesh, settings, control); },
      progress)};
}

void register_shape(py::module_& module) {
  py::class_<Shape>(module, "Shape", R"(A mesh preprocessed once for any number of matches.

Shape(V, F, **preprocess) cleans the mesh and computes what every match of it needs
(geodesic samples, the spectral basis, curvature): most of a match's time on large meshes.
V is float (n, 3), F int (m, 3). Keywords are the preprocessing settings of
isocorr.settings() (scope 'preprocess'), and `threads`.)")
      .def(py::init([](const VertexArray& vertices, const FaceArray& faces, const py::kwargs& kwargs) {
             MatchSettings settings;
             apply_settings(kwargs, {SettingScope::kPreprocess, SettingScope::kLocal}, settings);
             Shape shape{mesh_from_arrays(vertices, faces), nullptr};
             shape.shape = run_interruptibly<std::shared_ptr<const PreprocessedShape>>(
                 [&](const JobControl& control) {
                   return PreprocessedShape::build(shape.mesh, settings.preprocess,
                                                   control.with_threads(settings.threads));
                 },
                 py::none());
             return shape;
           }),
           py::arg("V"), py::arg("F"))
      .def_property_readonly("V", [](const Shape& s) { return py::object(arrays_from_mesh(s.mesh)[0]); },
                             "the vertex positions given, float64 (n, 3)")
      .def_property_readonly("F", [](const Shape& s) { return py::object(arrays_from_mesh(s.mesh)[1]); },
                             "the triangles given, int32 (m, 3)")
      .def_property_readonly("num_vertices", [](const Shape& s) { return s.mesh.num_vertices(); })
      .def_property_readonly(
          "basis", [](const Shape& s) { return basis_in_input_numbering(*s.shape); },
          "float32 (n, spectral_basis): Laplace-Beltrami eigenfunctions, one row per vertex given, "
          "orthonormal under the lumped mass matrix divided by the area; the basis of Match.C")
      .def_property_readonly(
          "eigenvalues",
          [](const Shape& s) {
            const Eigen::VectorXf& values = s.shape->spectral_eigenvalues();
            return float_array(std::vector<float>(values.data(), values.data() + values.size()));
          },
          "float32 (spectral_basis,): the basis's eigenvalues times the area, ascending")
      .def("__repr__", [](const Shape& s) {
        return "<isocorr.Shape: " + std::to_string(s.mesh.num_vertices()) + " vertices, " +
               std::to_string(s.mesh.num_faces()) + " faces>";
      });
}

void register_match_class(py::module_& module) {
  py::class_<Match>(module, "Match", "The result of isocorr.match: maps in the inputs' vertex numbering.")
      .def_property_readonly("forward", [](const Match& m) { return int_array(m.result.output.forward); },
                             "int32 (n_source,): the target vertex of each source vertex")
      .def_property_readonly("reverse", [](const Match& m) { return int_array(m.result.output.reverse); },
                             "int32 (n_target,): the source vertex of each target vertex (-1: none, for a part)")
      .def_property_readonly(
          "precise", [](const Match& m) { return precise_arrays(m.result.output.forward_precise); },
          "(faces, weights): each source vertex's point on the target, int32 faces (n_source,) of the target "
          "as given and float32 (n_source, 3) weights of their corners (isocorr.precise_map)")
      .def_property_readonly(
          "reverse_precise", [](const Match& m) { return precise_arrays(m.result.output.reverse_precise); },
          "(faces, weights): the same for each target vertex on the source (face -1: none, for a part)")
      .def_property_readonly("confidence",
                             [](const Match& m) { return float_array(m.result.output.forward_confidence); },
                             "float32 (n_source,): each forward pair's residual, lower is better")
      .def_property_readonly("reverse_confidence",
                             [](const Match& m) { return float_array(m.result.output.reverse_confidence); },
                             "float32 (n_target,): the same for the reverse map")
      .def_property_readonly(
          "report", [](const Match& m) { return py::module_::import("json").attr("loads")(m.result.output.report_json); },
          "the JSON report as a dict: settings, stage timings, candidates, why the winner won")
      .def_property_readonly(
          "C",
          [](const Match& m) -> py::object {
            const Eigen::MatrixXf& c = m.result.diagnostics.refinement.functional_map;
            if (c.size() == 0) return py::none();
            return matrix_array(c);
          },
          "float32 (k, k) or None: the refinement's last functional map over the first k columns of "
          "each Shape.basis, with source.basis[:, :k] @ C ~ target.basis[forward, :k] (it pulls target "
          "functions back to the source); None when the refinement did not run (part matching, refine=none)")
      .def_property_readonly("diso", [](const Match& m) { return m.result.quality.diso; },
                             "D_iso of the final map")
      .def_property_readonly("orientation", [](const Match& m) { return m.result.quality.orientation; },
                             "share of source faces whose image keeps its handedness")
      .def_property_readonly("verdict", [](const Match& m) { return std::string(m.result.verdict.status()); },
                             "'ok', or 'suspect' when a check of the result failed: look at the map before using it")
      .def_property_readonly("verdict_reasons", [](const Match& m) { return py::cast(m.result.verdict.reasons); },
                             "one sentence per failed check (empty when the verdict is 'ok')")
      .def_property_readonly("warnings", [](const Match& m) { return py::cast(m.result.messages.warnings); })
      .def_property_readonly("notes", [](const Match& m) { return py::cast(m.result.messages.notes); })
      .def("__repr__", [](const Match& m) {
        return "<isocorr.Match: " + std::to_string(m.result.output.forward.size()) + " -> " +
               std::to_string(m.result.output.reverse.size()) + " vertices, D_iso " +
               std::to_string(m.result.quality.diso) + ">";
      });
}

}  // namespace

void register_match(py::module_& module) {
  register_shape(module);
  register_match_class(module);
  module.def("match", &match, py::arg("source"), py::arg("target"), py::kw_only(), py::arg("progress") = py::none(),
             R"(Matches source to target: each an isocorr.Shape, or a (V, F) pair of arrays.

Keywords are the settings of isocorr.settings() (preprocessing ones only with (V, F)
pairs: a Shape keeps its own). progress, if given, is called as progress(stage, fraction)
from this thread. The GIL is released while matching; Ctrl-C cancels the match and raises
KeyboardInterrupt. Raises ValueError for an unusable mesh or setting.)");
}

}  // namespace isocorr::python
