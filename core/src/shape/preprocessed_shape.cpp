#include "isocorr/shape/preprocessed_shape.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "isocorr/sampling/salient_sampling.h"
#include "isocorr/util/parallel.h"

namespace isocorr {

std::string PreprocessOptions::key() const {
  std::ostringstream out;
  out << "agd" << saliency.agd_sources << "/ext" << saliency.extremity_radius << "/weld"
      << cleaning.weld_tolerance << "/largest" << cleaning.keep_largest_component << "/r0"
      << level0_radius << "/shrink" << level_shrink << "/k1" << decision_level << "/m"
      << max_level0_samples;
  return out.str();
}

std::shared_ptr<const PreprocessedShape> PreprocessedShape::build(const TriangleMesh& input,
                                                                  const PreprocessOptions& options,
                                                                  const JobControl& control) {
  if (options.level0_radius <= 0 || options.level0_radius >= 1)
    throw InputError("level-0 radius must lie in (0, 1) (fraction of the geodesic diameter)");
  if (options.level_shrink <= 0 || options.level_shrink >= 1)
    throw InputError("level shrink factor must lie in (0, 1)");
  if (options.decision_level < 1 || options.decision_level > 12)
    throw InputError("decision level K1 must lie in [1, 12]");
  if (options.max_level0_samples < 3 || options.max_level0_samples > 12)
    throw InputError("the number of level-0 samples must lie in [3, 12]");

  std::shared_ptr<PreprocessedShape> shape(new PreprocessedShape());
  shape->options_ = options;
  shape->clean_ = clean_mesh(input, options.cleaning);
  const TriangleMesh& mesh = shape->clean_.mesh;
  if (mesh.num_vertices() < 16)
    throw InputError("mesh has only " + std::to_string(mesh.num_vertices()) +
                     " usable vertices; at least 16 are needed to match");
  shape->topology_ = std::make_unique<MeshTopology>(mesh);
  shape->geodesics_ = std::make_unique<FastMarching>(mesh, *shape->topology_);
  shape->normals_ = vertex_normals(mesh);
  shape->area_ = total_area(mesh);
  shape->mean_edge_ = mean_edge_length(mesh);
  control.check_cancelled();

  const int threads = resolve_thread_count(options.threads);
  shape->saliency_ = compute_saliency(*shape->geodesics_, options.saliency, threads);
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
  const float inverse_diameter = static_cast<float>(1.0 / shape->diameter_);
  for (float& value : shape->fields_) value = value == kUnreached ? 1.f : value * inverse_diameter;
  return shape;
}

int PreprocessedShape::num_level0_samples() const {
  int count = 0;
  while (count < num_samples() && sample_steps_[count] == 0) ++count;
  return count;
}

size_t PreprocessedShape::memory_bytes() const {
  const size_t n = mesh().num_vertices();
  return fields_.size() * sizeof(float) + n * (sizeof(Vec3) * 2 + sizeof(float) + 3 * sizeof(int)) +
         mesh().faces.size() * sizeof(Face) * 3;
}

}  // namespace isocorr
