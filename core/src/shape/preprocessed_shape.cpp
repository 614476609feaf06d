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

namespace {

// The Laplace-Beltrami basis and the smoothed curvature: a few sparse solves, sequential.
struct SpectralPart {
  LaplaceBasis basis;
  SmoothedCurvature curvature;
};

SpectralPart compute_spectral_part(const TriangleMesh& mesh, const std::vector<Vec3>& normals,
                                   const PreprocessOptions& options, const JobControl& control) {
  LaplaceBasisOptions solver;
  solver.control = &control;
  SpectralPart part;
  part.basis = options.spectral_cells > 0
                   ? compute_reduced_laplace_basis(mesh, options.spectral_basis, options.spectral_cells, solver)
                   : compute_laplace_basis(mesh, options.spectral_basis, solver);
  control.check_cancelled();
  part.curvature = smoothed_mean_and_gaussian_curvature(mesh, normals);
  return part;
}

// Level 0's radius and sample cap, then a radius shrinking by level_shrink per level in
// half-steps down to the decision level, and one half-step beyond for the targets.
SamplingSchedule sampling_schedule(const PreprocessOptions& options, double diameter) {
  SamplingSchedule schedule;
  schedule.radii.push_back(options.level0_radius * diameter);
  schedule.max_new.push_back(options.max_level0_samples);
  for (int step = 1; step <= 2 * options.decision_level + 1; ++step) {
    schedule.radii.push_back(options.level0_radius * diameter *
                             std::pow(options.level_shrink, step / 2.0));
    schedule.max_new.push_back(0);
  }
  return schedule;
}

}  // namespace

std::shared_ptr<const PreprocessedShape> PreprocessedShape::build(const TriangleMesh& input,
                                                                  const PreprocessOptions& options,
                                                                  const JobControl& control) {
  validate_preprocess_options(options);

  std::shared_ptr<PreprocessedShape> shape(new PreprocessedShape());
  shape->options_ = options;
  shape->clean_and_measure(input, control);

  const int threads = resolve_thread_count(control.threads);
  // The eigensolver is sequential; with two or more threads it runs beside the geodesic
  // work below instead of after it (michael0, 52K vertices: 13.6 s -> see the commit).
  // It checks `control` too: a cancelled job must not wait for it (the future's
  // destructor joins it when the geodesic work below throws Cancelled).
  // The smoothed curvature, also a few sparse solves, goes with it.
  const TriangleMesh& mesh = shape->clean_.mesh;
  std::future<SpectralPart> spectral;
  if (options.spectral_basis > 0)
    spectral = std::async(threads > 1 ? std::launch::async : std::launch::deferred,
                          [&mesh, &options, &control, &shape] {
                            return compute_spectral_part(mesh, shape->normals_, options, control);
                          });
  shape->saliency_ = compute_saliency(*shape->geodesics_, options.saliency, threads, control);
  control.check_cancelled();

  const SampleSet samples = evenly_spaced_salient_sampling(
      *shape->geodesics_, shape->saliency_.order, sampling_schedule(options, shape->saliency_.diameter));
  shape->sample_vertices_ = samples.vertices;
  shape->sample_steps_ = samples.step;
  control.check_cancelled();
  shape->compute_sample_fields(threads, control);
  control.check_cancelled();

  if (spectral.valid()) {
    // The spectral samples are chosen before waiting for the eigensolver, so both run at once.
    shape->spectral_samples_ = spread_vertices(mesh, options.spectral_samples);
    SpectralPart part = spectral.get();
    shape->smoothed_curvature_ = std::move(part.curvature.mean);
    shape->smoothed_gaussian_curvature_ = std::move(part.curvature.gaussian);
    // Mass-orthonormal eigenvectors scaled by sqrt(area): the same shape at another scale
    // gets the same embedding, so spectral distances compare across meshes.
    const LaplaceBasis& solved = part.basis;
    if (!solved.eigenvectors.allFinite() || !solved.eigenvalues.allFinite())
      throw NumericalError("the Laplace-Beltrami basis has a non-finite value");
    shape->spectral_basis_ = (solved.eigenvectors * std::sqrt(shape->area_)).cast<float>();
    shape->spectral_eigenvalues_ = (solved.eigenvalues * shape->area_).cast<float>();
  }
  return shape;
}

void PreprocessedShape::clean_and_measure(const TriangleMesh& input, const JobControl& control) {
  clean_ = clean_mesh(input, options_.cleaning);
  const TriangleMesh& mesh = clean_.mesh;
  check_matchable(clean_);
  topology_ = std::make_unique<MeshTopology>(mesh);
  geodesics_ = std::make_unique<FastMarching>(mesh, *topology_);
  normals_ = vertex_normals(mesh);
  area_ = total_area(mesh);
  mean_edge_ = mean_edge_length(mesh);
  if (!(std::isfinite(area_) && area_ > 0 && std::isfinite(mean_edge_)))
    throw NumericalError("the surface area or edge lengths are not finite and positive");
  control.check_cancelled();
}

void PreprocessedShape::compute_sample_fields(int threads, const JobControl& control) {
  // One full field per sample: these are the anchors' fields at every level. The largest
  // value over all of them is the diameter used for normalisation: with hundreds of evenly
  // spread sources it is the same on two copies of a shape to within a sample spacing.
  const size_t n = mesh().num_vertices();
  fields_.assign(n * sample_vertices_.size(), 0.f);
  std::vector<FastMarching::Workspace> workspaces(threads);
  std::vector<float> farthest(sample_vertices_.size(), 0.f);
  parallel_for(num_samples(), threads, [&](int i, int worker) {
    control.check_cancelled();
    auto& ws = workspaces[worker];
    geodesics_->compute({sample_vertices_[i]}, ws);
    float* row = fields_.data() + i * n;
    for (size_t v = 0; v < n; ++v) {
      row[v] = ws.distance[v];
      if (row[v] != kUnreached) farthest[i] = std::max(farthest[i], row[v]);
    }
  });
  diameter_ = std::max<double>(saliency_.diameter, *std::max_element(farthest.begin(), farthest.end()));
  if (!(std::isfinite(diameter_) && diameter_ > 0))
    throw NumericalError("the geodesic diameter is not finite and positive");
  const float inverse_diameter = static_cast<float>(1.0 / diameter_);
  for (float& value : fields_) value = value == kUnreached ? 1.f : value * inverse_diameter;
  const int sample_count = num_samples();
  sample_fields_.resize(static_cast<size_t>(sample_count) * sample_count);
  for (int i = 0; i < sample_count; ++i)
    for (int j = 0; j < sample_count; ++j)
      sample_fields_[static_cast<size_t>(i) * sample_count + j] = field(i, sample_vertex(j));
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
         mesh().faces.size() * (sizeof(Face) * 3 + sizeof(CleanMesh::InputFace));
}

}  // namespace isocorr
