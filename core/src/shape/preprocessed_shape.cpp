#include "isocorr/shape/preprocessed_shape.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <utility>

#include "isocorr/sampling/salient_sampling.h"
#include "isocorr/sampling/vertex_spreading.h"
#include "isocorr/settings/settings_schema.h"
#include "isocorr/shape/mean_curvature.h"
#include "isocorr/spectral/reduced_laplace_basis.h"
#include "isocorr/util/parallel.h"

namespace isocorr {

std::string PreprocessOptions::key() const {
  MatchSettings settings;
  settings.preprocess = *this;
  return settings_key(settings, SettingScope::kPreprocess);
}

std::shared_ptr<const PreprocessedShape> PreprocessedShape::build(const TriangleMesh& input,
                                                                  const PreprocessOptions& options,
                                                                  const JobControl& control) {
  validate_preprocess_options(options);

  std::shared_ptr<PreprocessedShape> shape(new PreprocessedShape());
  shape->options_ = options;
  shape->clean_ = clean_mesh(input, options.cleaning);
  const TriangleMesh& mesh = shape->clean_.mesh;
  check_matchable(shape->clean_);
  shape->topology_ = std::make_unique<MeshTopology>(mesh);
  shape->geodesics_ = std::make_unique<FastMarching>(mesh, *shape->topology_);
  shape->normals_ = vertex_normals(mesh);
  shape->area_ = total_area(mesh);
  shape->mean_edge_ = mean_edge_length(mesh);
  if (!(std::isfinite(shape->area_) && shape->area_ > 0 && std::isfinite(shape->mean_edge_)))
    throw NumericalError("the surface area or edge lengths are not finite and positive");
  control.check_cancelled();

  const int threads = resolve_thread_count(options.threads);
  // The eigensolver is sequential; with two or more threads it runs beside the geodesic
  // work below instead of after it (michael0, 52K vertices: 13.6 s -> see the commit).
  // It checks `control` too: a cancelled job must not wait for it (the future's
  // destructor joins it when the geodesic work below throws Cancelled).
  // The smoothed curvature, also a few sparse solves, goes with it.
  auto compute_spectral = [&mesh, &options, &control, &shape] {
    LaplaceBasisOptions solver;
    solver.control = &control;
    LaplaceBasis basis =
        options.spectral_cells > 0
            ? compute_reduced_laplace_basis(mesh, options.spectral_basis, options.spectral_cells, solver)
            : compute_laplace_basis(mesh, options.spectral_basis, solver);
    control.check_cancelled();
    SmoothedCurvature curvature = smoothed_mean_and_gaussian_curvature(mesh, shape->normals_);
    shape->smoothed_curvature_ = std::move(curvature.mean);
    shape->smoothed_gaussian_curvature_ = std::move(curvature.gaussian);
    return basis;
  };
  std::future<LaplaceBasis> basis;
  if (options.spectral_basis > 0)
    basis = std::async(threads > 1 ? std::launch::async : std::launch::deferred, compute_spectral);
  shape->saliency_ = compute_saliency(*shape->geodesics_, options.saliency, threads, control);
  control.check_cancelled();

  SamplingSchedule schedule;
  const double diameter = shape->saliency_.diameter;
  schedule.radii.push_back(options.level0_radius * diameter);
  schedule.max_new.push_back(options.max_level0_samples);
  for (int step = 1; step <= 2 * options.decision_level + 1; ++step) {
    schedule.radii.push_back(options.level0_radius * diameter *
                             std::pow(options.level_shrink, step / 2.0));
    schedule.max_new.push_back(0);
  }
  const SampleSet samples =
      evenly_spaced_salient_sampling(*shape->geodesics_, shape->saliency_.order, schedule);
  shape->sample_vertices_ = samples.vertices;
  shape->sample_steps_ = samples.step;
  control.check_cancelled();

  // One full field per sample: these are the anchors' fields at every level. The largest
  // value over all of them is the diameter used for normalisation: with hundreds of evenly
  // spread sources it is the same on two copies of a shape to within a sample spacing.
  const size_t n = mesh.num_vertices();
  shape->fields_.assign(n * samples.vertices.size(), 0.f);
  std::vector<FastMarching::Workspace> workspaces(threads);
  std::vector<float> farthest(samples.vertices.size(), 0.f);
  parallel_for(shape->num_samples(), threads, [&](int i, int worker) {
    control.check_cancelled();
    auto& ws = workspaces[worker];
    shape->geodesics_->compute({samples.vertices[i]}, ws);
    float* row = shape->fields_.data() + i * n;
    for (size_t v = 0; v < n; ++v) {
      row[v] = ws.distance[v];
      if (row[v] != kUnreached) farthest[i] = std::max(farthest[i], row[v]);
    }
  });
  shape->diameter_ = std::max<double>(diameter, *std::max_element(farthest.begin(), farthest.end()));
  if (!(std::isfinite(shape->diameter_) && shape->diameter_ > 0))
    throw NumericalError("the geodesic diameter is not finite and positive");
  const float inverse_diameter = static_cast<float>(1.0 / shape->diameter_);
  for (float& value : shape->fields_) value = value == kUnreached ? 1.f : value * inverse_diameter;
  const int sample_count = shape->num_samples();
  shape->sample_fields_.resize(static_cast<size_t>(sample_count) * sample_count);
  for (int i = 0; i < sample_count; ++i)
    for (int j = 0; j < sample_count; ++j)
      shape->sample_fields_[static_cast<size_t>(i) * sample_count + j] = shape->field(i, shape->sample_vertex(j));
  control.check_cancelled();

  if (basis.valid()) {
    // The spectral samples are chosen before waiting for the eigensolver, so both run at once.
    shape->spectral_samples_ = spread_vertices(mesh, options.spectral_samples);
    // Mass-orthonormal eigenvectors scaled by sqrt(area): the same shape at another scale
    // gets the same embedding, so spectral distances compare across meshes.
    const LaplaceBasis solved = basis.get();
    if (!solved.eigenvectors.allFinite() || !solved.eigenvalues.allFinite())
      throw NumericalError("the Laplace-Beltrami basis has a non-finite value");
    shape->spectral_basis_ = (solved.eigenvectors * std::sqrt(shape->area_)).cast<float>();
    shape->spectral_eigenvalues_ = (solved.eigenvalues * shape->area_).cast<float>();
  }
  return shape;
}

int PreprocessedShape::num_level0_samples() const {
  int count = 0;
  while (count < num_samples() && sample_steps_[count] == 0) ++count;
  return count;
}

size_t PreprocessedShape::memory_bytes() const {
  const size_t n = mesh().num_vertices();
  const size_t floats = fields_.size() + sample_fields_.size() + spectral_basis_.size() + smoothed_curvature_.size() +
                        smoothed_gaussian_curvature_.size();
  return floats * sizeof(float) + spectral_samples_.size() * sizeof(int) + n * (sizeof(Vec3) * 2 + sizeof(float) + 3 * sizeof(int)) +
         mesh().faces.size() * sizeof(Face) * 3;
}

}  // namespace isocorr
