// The evidence part maps compete on, whatever made them (measure_part_maps, part_matching.h).
#include <algorithm>
#include <vector>

#include "isocorr/matching/orientation.h"
#include "isocorr/partial/part_matching.h"
#include "isocorr/util/parallel.h"
#include "part_geometry.h"

namespace isocorr {
namespace {

// Fields on the target per dense map weighed by measure_part_maps (as the complete pipeline's
// dense choice: 16 spread samples against all give a stable mean).
constexpr int kPartEvidenceSources = 16;

// Everything but the curvature, which needs every map's kappa first (measure_part_maps).
PartMapEvidence measure_with(const PartGeometry& part, const std::vector<int>& forward, int threads) {
  const PreprocessedShape& source = part.shape;
  const PreprocessedShape& target = part.target;
  PartMapEvidence evidence;
  evidence.orientation =
      dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(), target.normals(), forward);
  // Every sample against the first kPartEvidenceSources (farthest-point order: spread over
  // the part), their images' distances raw from fields on the target.
  const int samples = source.num_samples();
  const int sources = std::min(samples, kPartEvidenceSources);
  std::vector<std::vector<float>> source_distance(sources, std::vector<float>(samples)),
      target_distance(sources, std::vector<float>(samples));
  std::vector<std::vector<char>> exact(sources, std::vector<char>(samples)),
      target_exact(sources, std::vector<char>(samples));
  parallel_for(sources, threads, [&](int a, int) {
    const std::vector<float> field = target.geodesics().distance_field(forward[source.sample_vertex(a)]);
    for (int b = 0; b < samples; ++b) {
      const int v = source.sample_vertex(b);
      source_distance[a][b] = part.distance(a, v);
      target_distance[a][b] = field[forward[v]];
      exact[a][b] = part.exact(a, v, source_distance[a][b]);
      target_exact[a][b] = part.target_exact(forward[source.sample_vertex(a)], forward[v], target_distance[a][b]);
    }
  });
  std::vector<double> ratios;
  for (int a = 0; a < sources; ++a)
    for (int b = 0; b < samples; ++b)
      if (b != a && target_distance[a][b] > 0 && exact[a][b] && target_exact[a][b])
        ratios.push_back(source_distance[a][b] / target_distance[a][b]);
  if (!ratios.empty()) {
    std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
    evidence.scale = ratios[ratios.size() / 2];
  }
  double sum = 0;
  long count = 0;
  for (int a = 0; a < sources; ++a)
    for (int b = 0; b < samples; ++b)
      if (b != a) {
        sum += mismatch(source_distance[a][b], static_cast<float>(evidence.scale * target_distance[a][b]), exact[a][b],
                        target_exact[a][b]);
        ++count;
      }
  evidence.distortion = count ? sum / count / source.diameter() : 0.0;
  return evidence;
}

}  // namespace

std::vector<PartMapEvidence> measure_part_maps(const PreprocessedShape& source, const PreprocessedShape& target,
                                               const std::vector<const std::vector<int>*>& forwards, int threads) {
  const PartGeometry part(source, target);
  std::vector<PartMapEvidence> evidence;
  for (const std::vector<int>* forward : forwards) evidence.push_back(measure_with(part, *forward, threads));
  // The part smoothed once per map's kappa, side by side.
  std::vector<double> scales;
  for (const PartMapEvidence& e : evidence) scales.push_back(e.scale);
  const PartCurvature curvature(part, scales, threads);
  for (size_t i = 0; i < evidence.size(); ++i) evidence[i].curvature = curvature.disagreement(*forwards[i], scales[i]);
  return evidence;
}

}  // namespace isocorr
