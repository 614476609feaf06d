#include "isocorr/refinement/candidate_screening.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include "isocorr/matching/orientation.h"
#include "isocorr/refinement/dense_choice.h"
#include "isocorr/sampling/vertex_spreading.h"
#include "isocorr/shape/mean_curvature.h"
#include "isocorr/util/parallel.h"

namespace isocorr {

SpectralSide spectral_side(const PreprocessedShape& shape) {
  return SpectralSide{&shape.spectral_basis(),      &shape.geodesics().topology(),
                      &shape.spectral_samples(),    &shape.spectral_eigenvalues(),
                      &shape.smoothed_curvature(), &shape.smoothed_gaussian_curvature()};
}

std::vector<int> spread_sample_map(const std::vector<int>& nearest_sample, const std::vector<int>& sample_images) {
  std::vector<int> forward(nearest_sample.size());
  for (size_t v = 0; v < forward.size(); ++v) forward[v] = sample_images[nearest_sample[v]];
  return forward;
}

std::vector<ScreenedStart> screen_tracked_maps(const PreprocessedShape& source, const PreprocessedShape& target,
                                               const std::vector<TrackedMap>& tracked, const std::vector<int>& starts,
                                               int k_end, const ZoomOutOptions& options,
                                               const JobControl& control,
                                               const std::vector<std::pair<int, int>>& fixed_pairs) {
  // The spectral samples are in farthest-point order: any prefix is evenly spread.
  auto first_samples = [](const PreprocessedShape& shape) {
    const std::vector<int>& all = shape.spectral_samples();
    return std::vector<int>(all.begin(), all.begin() + std::min<size_t>(all.size(), kScreenSamples));
  };
  const std::vector<int> source_samples = first_samples(source), target_samples = first_samples(target);
  SpectralSide source_side = spectral_side(source), target_side = spectral_side(target);
  source_side.samples = &source_samples;
  target_side.samples = &target_samples;
  const std::vector<int> nearest_sample =
      nearest_centre(source.geodesics().topology(), source.mesh().num_vertices(), source_samples);
  // The starts are independent: each is screened whole on one worker (its own loops on one
  // thread), which keeps both cores busy where the screen's small per-iteration loops
  // could not (a 5K pair's 32 starts: about 1.1 s on one core).
  const JobControl one_thread = control.with_threads(1);
  std::vector<ScreenedStart> screened(starts.size());
  parallel_for(static_cast<int>(starts.size()), resolve_thread_count(control.threads), [&](int i, int) {
    const int index = starts[i];
    std::vector<std::pair<int, int>> start = fixed_pairs;
    for (const SamplePair& p : tracked[index].pairs)
      start.emplace_back(source.sample_vertex(p.source_sample), image_vertex(target, p));
    ScreenedStart& s = screened[i];
    s.evidence.tracked_index = index;
    s.sampled = zoomout_on_samples(source_side, target_side, start, k_end, options, one_thread);
    s.evidence.orientation = dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(),
                                                         target.normals(),
                                                         spread_sample_map(nearest_sample, s.sampled.images));
    std::vector<std::pair<int, int>> pairs;
    for (size_t j = 0; j < source_samples.size(); ++j) pairs.emplace_back(source_samples[j], s.sampled.images[j]);
    s.evidence.curvature = curvature_disagreement(source.smoothed_curvature(), target.smoothed_curvature(), pairs);
  });
  return screened;
}

bool same_images(const std::vector<int>& a, const std::vector<int>& b, const MeshTopology& target_topology) {
  constexpr double kSameMapShare = 0.8;
  int same = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const int x = a[i], y = b[i];
    same += x == y || std::find(target_topology.neighbours_begin(x), target_topology.neighbours_end(x), y) !=
                          target_topology.neighbours_end(x);
  }
  return !a.empty() && a.size() == b.size() && same >= kSameMapShare * a.size();
}

std::vector<ScreenedStart> starts_to_refine(std::vector<ScreenedStart> screened, int count, double orientation_margin,
                                            const MeshTopology& target_topology) {
  double best_orientation = 0;
  for (const ScreenedStart& s : screened) best_orientation = std::max(best_orientation, s.evidence.orientation);
  const double threshold = mirror_threshold(best_orientation, orientation_margin);
  auto mirrored = [&](size_t i) { return screened[i].evidence.orientation < threshold; };
  std::vector<size_t> by_screen(screened.size());
  std::iota(by_screen.begin(), by_screen.end(), 0);
  std::stable_sort(by_screen.begin(), by_screen.end(), [&](size_t a, size_t b) {
    if (mirrored(a) != mirrored(b)) return mirrored(b);
    return screened[a].evidence.curvature < screened[b].evidence.curvature;
  });
  std::vector<bool> considered(screened.size(), false);
  std::vector<size_t> picked;
  auto take = [&](size_t i) {
    if (considered[i] || static_cast<int>(picked.size()) >= count) return;
    considered[i] = true;
    for (const size_t other : picked)
      if (same_images(screened[other].sampled.images, screened[i].sampled.images, target_topology)) return;
    picked.push_back(i);
  };
  for (size_t i = 0; i < screened.size(); ++i) {
    if (!mirrored(i)) take(i);
    take(by_screen[i]);
  }
  std::vector<ScreenedStart> starts;
  for (const size_t i : picked) starts.push_back(std::move(screened[i]));
  return starts;
}

}  // namespace isocorr
