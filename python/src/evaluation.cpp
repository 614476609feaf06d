#include "evaluation.h"

#include <pybind11/stl.h>

#include <limits>
#include <string>
#include <vector>

#include "isocorr/eval/metrics.h"
#include "isocorr/geodesic/geodesic_diameter.h"
#include "isocorr/output/map_files.h"
#include "numpy_mesh.h"

namespace isocorr::python {
namespace {

// The target's geodesics, computed once per call.
struct TargetGeodesics {
  explicit TargetGeodesics(TriangleMesh target_mesh)
      : mesh(std::move(target_mesh)), topology(mesh), geodesics(mesh, topology),
        diameter(estimate_geodesic_diameter(geodesics)) {}
  TriangleMesh mesh;
  MeshTopology topology;
  FastMarching geodesics;
  double diameter;
};

// The ground truth of a call: `truth` one true target vertex per source vertex (-1:
// unknown), `mirrored` the mirror image of each true target vertex (optional).
GroundTruth ground_truth(const std::vector<int>& truth, const std::vector<int>& mirrored, int target_vertices) {
  GroundTruth gt;
  for (size_t v = 0; v < truth.size(); ++v) {
    if (truth[v] < 0) continue;
    if (truth[v] >= target_vertices)
      throw py::value_error("truth[" + std::to_string(v) + "] = " + std::to_string(truth[v]) + " is outside the target");
    gt.source.push_back(static_cast<int>(v));
    gt.target.push_back(truth[v]);
    if (!mirrored.empty()) gt.mirrored_target.push_back(mirrored[v]);
  }
  gt.description = "given: " + std::to_string(gt.source.size()) + " pairs";
  return gt;
}

py::dict evaluate(const VertexArray& vertices, const FaceArray& faces, const IndexArray& forward_array,
                  const IndexArray& truth_array, const py::object& mirrored_array, int max_points) {
  const std::vector<int> forward = index_vector(forward_array, "forward");
  const std::vector<int> truth = index_vector(truth_array, "truth");
  const std::vector<int> mirrored =
      mirrored_array.is_none() ? std::vector<int>() : index_vector(mirrored_array.cast<IndexArray>(), "mirrored");
  if (truth.size() != forward.size())
    throw py::value_error("truth has " + std::to_string(truth.size()) + " entries for " +
                          std::to_string(forward.size()) + " source vertices");
  if (!mirrored.empty() && mirrored.size() != truth.size())
    throw py::value_error("mirrored must have one entry per source vertex, as truth");
  const TargetGeodesics target(mesh_from_arrays(vertices, faces));
  check_map_fits(forward, static_cast<int>(forward.size()), target.mesh.num_vertices());
  const GroundTruth gt = ground_truth(truth, mirrored, target.mesh.num_vertices());
  EvaluationOptions options;
  options.max_points = max_points;
  GroundTruthScore score;
  {
    py::gil_scoped_release released;
    score = score_against_ground_truth(target.mesh, target.geodesics, target.diameter, forward, gt, options);
  }
  py::dict out;
  out["evaluated"] = score.evaluated;
  out["d_grd"] = score.mean_error;
  out["d_grd_max"] = score.max_error;
  out["kim_mean"] = score.mean_kim_error;
  out["kim_auc"] = score.kim_auc;
  out["kim_thresholds"] = py::array_t<double>(score.kim_thresholds.size(), score.kim_thresholds.data());
  out["kim_curve"] = py::array_t<double>(score.kim_curve.size(), score.kim_curve.data());
  out["mirrored_fraction"] = score.mirrored_fraction;
  out["far_fraction"] = score.far_fraction;
  out["flip_free"] = score.flip_free;
  out["flip_rule"] = score.flip_rule;
  out["point_sources"] = int_array(score.point_sources);
  out["point_errors"] = py::array_t<double>(score.point_errors.size(), score.point_errors.data());
  return out;
}

}  // namespace

void register_evaluation(py::module_& module) {
  module.def("evaluate", &evaluate, py::arg("V"), py::arg("F"), py::arg("forward"), py::arg("truth"),
             py::kw_only(), py::arg("mirrored") = py::none(), py::arg("max_points") = 2000,
             R"(Scores `forward` (source vertex -> target vertex) against `truth` (the true target
vertex of each source vertex, -1 where unknown) on the target mesh (V, F), as `isocorr eval`.

Returns a dict: d_grd (mean geodesic error / target diameter), d_grd_max, kim_mean (mean
error / sqrt(area)), kim_thresholds and kim_curve (Kim et al.'s cumulative curve) and
kim_auc, far_fraction, flip_free and flip_rule, point_sources and point_errors (per scored
point, error / diameter), and, with `mirrored` (the mirror image of each true target
vertex), mirrored_fraction. At most max_points pairs are scored, evenly strided (0: all).)");
  module.def(
      "coverage",
      [](const VertexArray& vertices, const FaceArray& faces, const IndexArray& forward_array,
         const std::vector<int>& seed_counts) {
        const std::vector<int> forward = index_vector(forward_array, "forward");
        const TargetGeodesics target(mesh_from_arrays(vertices, faces));
        check_map_fits(forward, static_cast<int>(forward.size()), target.mesh.num_vertices());
        py::gil_scoped_release released;
        return coverage(target.mesh, target.geodesics, forward, seed_counts);
      },
      py::arg("V"), py::arg("F"), py::arg("forward"), py::arg("seed_counts") = std::vector<int>{10, 20, 50, 100, 200, 500},
      R"(SHREC'20 coverage of the target (V, F) by the images of `forward`: for each count of
farthest-point seeds, the share of the target's area whose Voronoi cell holds an image.)");
}

}  // namespace isocorr::python
