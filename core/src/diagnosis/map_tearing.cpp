#include "isocorr/diagnosis/map_tearing.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace isocorr {
float sample_field_distance_bound(const PreprocessedShape& shape, int x, int y) {
  float largest = 0;
  for (int i = 0; i < shape.num_samples(); ++i)
    largest = std::max(largest, std::abs(shape.field(i, x) - shape.field(i, y)));
  return largest;
}

MapTearing measure_map_tearing(const PreprocessedShape& source, const PreprocessedShape& target,
                               const std::vector<int>& forward) {
  MapTearing tearing;
  const int samples = source.num_samples();
  if (samples < 2 || target.num_samples() == 0) return tearing;
  std::vector<int> others(samples);
  for (int a = 0; a < samples; ++a) {
    std::iota(others.begin(), others.end(), 0);
    std::swap(others[a], others.back());
    others.pop_back();
    const int nearest = std::min<int>(kTearNeighbours, static_cast<int>(others.size()));
    std::partial_sort(others.begin(), others.begin() + nearest, others.end(),
                      [&](int b, int c) { return source.sample_field(a, b) < source.sample_field(a, c); });
    const int image = forward[source.sample_vertex(a)];
    bool torn = false;
    for (int k = 0; k < nearest; ++k) {
      const int b = others[k];
      const float apart = source.sample_field(a, b);
      const int other_image = forward[source.sample_vertex(b)];
      if (!(apart > 0) || image < 0 || other_image < 0) continue;
      ++tearing.pairs;
      if (sample_field_distance_bound(target, image, other_image) > kTearStretch * apart) {
        ++tearing.torn_pairs;
        torn = true;
      }
    }
    tearing.torn_samples += torn;
    others.resize(samples);
  }
  return tearing;
}

}  // namespace isocorr
