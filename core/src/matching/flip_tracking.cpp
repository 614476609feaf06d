#include "isocorr/matching/flip_tracking.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "isocorr/matching/orientation.h"
#include "isocorr/matching/surface_descent.h"

namespace isocorr {
namespace {

// Geodesic distances to the anchors, laid out for the inner loops of matching: a source
// vertex's distances to the anchors' sources, and for every target sample of the pool a
// contiguous row of its distances to the anchors' images. Each level compares every new
// source sample with many pool samples, so reading rows instead of scattering over the
// anchors' fields makes tracking faster with the same numbers (cat0 -> cat2: 1.30 -> 1.08 s).
struct AnchorDistances {
  size_t anchor_count = 0;
  std::vector<float> pool_rows;  // pool.size() x anchor_count

  AnchorDistances(const PreprocessedShape& target, const std::vector<SamplePair>& anchors, size_t count,
                  const std::vector<int>& pool)
      : anchor_count(count), pool_rows(pool.size() * count) {
    for (size_t j = 0; j < pool.size(); ++j)
      for (size_t a = 0; a < count; ++a) pool_rows[j * count + a] = target.sample_field(anchors[a].target_sample, pool[j]);
  }
  const float* pool_row(size_t j) const { return pool_rows.data() + j * anchor_count; }
};

void distances_to_anchor_sources(const PreprocessedShape& source, const std::vector<SamplePair>& anchors,
                                 int source_sample, std::vector<float>& out) {
  out.resize(anchors.size());
  for (size_t a = 0; a < anchors.size(); ++a) out[a] = source.sample_field(anchors[a].source_sample, source_sample);
}

// The sum of term(0 .. n-1) and the largest term. The sum runs in four double lanes by
// position (i % 4), added in lane order at the end; written as four independent chains so
// that the compiler can keep them in one vector register (this loop runs for every
// candidate of every tracked sample).
struct TermTotals {
  double total = 0;
  float largest = 0;
};

template <class Term>
TermTotals total_and_largest(size_t n, const Term& term) {
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  float m0 = 0, m1 = 0, m2 = 0, m3 = 0;
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const float t0 = term(i), t1 = term(i + 1), t2 = term(i + 2), t3 = term(i + 3);
    s0 += t0, s1 += t1, s2 += t2, s3 += t3;
    m0 = std::max(m0, t0), m1 = std::max(m1, t1), m2 = std::max(m2, t2), m3 = std::max(m3, t3);
  }
  double* lanes[] = {&s0, &s1, &s2, &s3};
  float* maxima[] = {&m0, &m1, &m2, &m3};
  for (; i < n; ++i) {
    *lanes[i % 4] += term(i);
    *maxima[i % 4] = std::max(*maxima[i % 4], term(i));
  }
  return {s0 + s1 + s2 + s3, std::max(std::max(m0, m1), std::max(m2, m3))};
}

// d_iso(s, t | anchors) from s's distances to the first `count` anchors' sources and t's to
// their images,
// with the largest `trim` share of the terms left out: a trimmed mean, so that a few
// misplaced anchors or a non-isometric part (a cat's tail) do not decide the match.
// `skip` (or -1) leaves one anchor out entirely. A candidate whose distortion is certainly
// above `to_beat` (the best so far) gets +infinity without the selection of its kept terms,
// which is most of the cost: the kept terms sum to at least the total less the dropped
// count times the largest term, and far candidates fail that test. The terms are only
// stored for the candidates that pass it.
float anchored_distortion(const float* source_distances, const float* target_distances, size_t count, int skip,
                          double trim, float to_beat, std::vector<float>& scratch) {
  const bool skipping = skip >= 0 && static_cast<size_t>(skip) < count;
  const size_t size = count - (skipping ? 1 : 0);
  if (size == 0) return 0.f;
  // Term i is anchor i's, or anchor i + 1's past the skipped one.
  const size_t gap = skipping ? static_cast<size_t>(skip) : count;
  auto term = [&](size_t i) {
    const size_t a = i < gap ? i : i + 1;
    return std::abs(source_distances[a] - target_distances[a]);
  };
  const size_t kept = std::max<size_t>(1, static_cast<size_t>(std::lround(size * (1.0 - trim))));
  if (kept < size) {
    const TermTotals totals = total_and_largest(size, term);
    const size_t dropped = size - kept;
    const double least_mean = (totals.total - static_cast<double>(dropped) * totals.largest) / kept;
    // The margin covers the rounding of the sums: a pruned candidate could not have won.
    const double limit = 1.0001 * static_cast<double>(to_beat);
    if (least_mean > limit) return std::numeric_limits<float>::infinity();
    // A tighter bound where one large term (a misplaced anchor) loosens the first: the
    // dropped terms sum to at most all those above half the largest, plus half the largest
    // for each of the others.
    const float half = 0.5f * totals.largest;
    double above = 0;
    size_t count_above = 0;
    for (size_t i = 0; i < size; ++i) {
      const float t = term(i);
      above += t > half ? t : 0.f;
      count_above += t > half;
    }
    if (count_above <= dropped &&
        (totals.total - above - static_cast<double>(dropped - count_above) * half) / kept > limit)
      return std::numeric_limits<float>::infinity();
  }
  scratch.resize(size);
  for (size_t i = 0; i < size; ++i) scratch[i] = term(i);
  if (kept < size) std::nth_element(scratch.begin(), scratch.begin() + kept, scratch.end());
  double sum = 0;
  for (size_t i = 0; i < kept; ++i) sum += scratch[i];
  return static_cast<float>(sum / kept);
}

// Level-0 samples are only roughly aligned on the two shapes (each mesh is sampled on its
// own), and an early pair that is off by a sample spacing biases every later choice. After
// each level every pair is therefore re-chosen near its current image against all the
// other pairs (leave-one-out), which moves such anchors to where the later ones agree.
void reassign_pairs(const PreprocessedShape& source, const PreprocessedShape& target,
                    const std::vector<int>& pool, double radius, const TrackingOptions& options,
                    std::vector<SamplePair>& pairs) {
  const std::vector<SamplePair> anchors = pairs;
  const size_t anchor_count = std::min(anchors.size(), static_cast<size_t>(options.anchor_cap));
  const AnchorDistances distances(target, anchors, anchor_count, pool);
  std::vector<float> source_distances, scratch;
  for (size_t p = 0; p < pairs.size(); ++p) {
    distances_to_anchor_sources(source, anchors, pairs[p].source_sample, source_distances);
    const int current = pairs[p].target_sample;
    int best = current;
    float best_cost = std::numeric_limits<float>::max();
    for (size_t j = 0; j < pool.size(); ++j) {
      if (target.sample_field(current, pool[j]) > radius) continue;
      const float cost = anchored_distortion(source_distances.data(), distances.pool_row(j), anchor_count,
                                             static_cast<int>(p), options.trim_fraction, best_cost, scratch);
      if (cost < best_cost) best_cost = cost, best = pool[j];
    }
    pairs[p].target_sample = best;
    pairs[p].diso = best_cost;
  }
}

// Target samples are up to half a sample spacing from the true images, which scrambles
// the small triangles of the orientation test. Each pair's image is therefore also
// sought among all target vertices (descent from its sample against the anchors' fields,
// which cover every vertex): no new geodesics are needed.
void refine_to_vertices(const PreprocessedShape& source, const PreprocessedShape& target,
                        const TrackingOptions& options, std::vector<SamplePair>& pairs) {
  const size_t anchor_count = std::min(pairs.size(), static_cast<size_t>(options.anchor_cap));
  const MeshTopology& topology = target.geodesics().topology();
  // Pair p's anchors are the first anchor_count pairs but p itself: their distances from
  // p's source sample, and the fields of their images.
  std::vector<float> anchor_distances;
  std::vector<const float*> anchor_fields;
  for (size_t p = 0; p < pairs.size(); ++p) {
    anchor_distances.clear();
    anchor_fields.clear();
    for (size_t a = 0; a < anchor_count; ++a) {
      if (a == p) continue;
      anchor_distances.push_back(source.sample_field(pairs[a].source_sample, pairs[p].source_sample));
      anchor_fields.push_back(target.field_row(pairs[a].target_sample));
    }
    const size_t count = anchor_distances.size();
    // Four independent sums: one chain of dependent additions made this descent half of
    // tracking's time (TOSCA 5k, about 300 pairs and 100 anchors per tracked map).
    auto cost = [&](int w) {
      float s0 = 0, s1 = 0, s2 = 0, s3 = 0;
      size_t a = 0;
      for (; a + 4 <= count; a += 4) {
        s0 += std::abs(anchor_distances[a] - anchor_fields[a][w]);
        s1 += std::abs(anchor_distances[a + 1] - anchor_fields[a + 1][w]);
        s2 += std::abs(anchor_distances[a + 2] - anchor_fields[a + 2][w]);
        s3 += std::abs(anchor_distances[a + 3] - anchor_fields[a + 3][w]);
      }
      for (; a < count; ++a) s0 += std::abs(anchor_distances[a] - anchor_fields[a][w]);
      return (s0 + s1) + (s2 + s3);
    };
    float best = 0;
    pairs[p].target_vertex = descend_to_minimum(topology, target.sample_vertex(pairs[p].target_sample), cost, best);
  }
}

}  // namespace

double sample_map_diso(const PreprocessedShape& source, const PreprocessedShape& target,
                       const std::vector<SamplePair>& pairs) {
  if (pairs.size() < 2) return 0;
  double total = 0;
  for (size_t p = 0; p < pairs.size(); ++p) {
    const int tv = image_vertex(target, pairs[p]);
    double sum = 0;
    for (size_t q = 0; q < pairs.size(); ++q) {
      if (q == p) continue;
      sum += std::abs(source.sample_field(pairs[q].source_sample, pairs[p].source_sample) -
                      target.field(pairs[q].target_sample, tv));
    }
    total += sum / (pairs.size() - 1);
  }
  return total / pairs.size();
}

TrackedMap track_map(const PreprocessedShape& source, const PreprocessedShape& target,
                     const Level0Map& map, int rank, const TrackingOptions& options,
                     const JobControl& control) {
  TrackedMap tracked;
  tracked.level0_rank = rank;
  tracked.level0_diso = map.diso;
  const int m = static_cast<int>(map.target_of.size());
  std::vector<unsigned char> matched(source.num_samples(), 0);
  for (int i = 0; i < m; ++i) {
    tracked.pairs.push_back({i, map.target_of[i], 0.f});
    matched[i] = 1;
  }
  const int levels = std::min(source.options().decision_level, target.options().decision_level);
  const double r0 = source.options().level0_radius, shrink = source.options().level_shrink;
  std::vector<float> source_distances, scratch;
  for (int level = 1; level <= levels; ++level) {
    control.check_cancelled();
    const std::vector<SamplePair> anchors = tracked.pairs;  // pairs of earlier levels
    const size_t anchor_count = std::min(anchors.size(), static_cast<size_t>(options.anchor_cap));
    // Offering only this level's target samples (as the paper's patches do) leaves the
    // true image up to half a coarse spacing from any candidate; with per-sample matching
    // the finest samples can be offered at every level (options.pool_all_levels).
    const int pool_step = options.pool_all_levels ? std::numeric_limits<int>::max() : 2 * level + 1;
    std::vector<int> pool;
    for (int j = 0; j < target.num_samples(); ++j)
      if (target.sample_step(j) <= pool_step) pool.push_back(j);
    const double radius = r0 * std::pow(shrink, level);
    const AnchorDistances distances(target, anchors, anchor_count, pool);

    for (int s = 0; s < source.num_samples(); ++s) {
      if (matched[s] || source.sample_step(s) > 2 * level) continue;
      const int sv = source.sample_vertex(s);
      // Parent: the nearest sample matched at an earlier level.
      distances_to_anchor_sources(source, anchors, s, source_distances);
      const size_t parent_index = static_cast<size_t>(
          std::min_element(source_distances.begin(), source_distances.end()) - source_distances.begin());
      const SamplePair* parent = &anchors[parent_index];
      const float parent_distance = source_distances[parent_index];
      const double window = options.window_factor * parent_distance + radius;
      // Passes widen the search when nothing qualifies: near the parent's image and
      // keeping handedness, then near the parent's image, then anywhere.
      std::optional<HandednessGuard> guard;
      if (options.handedness_guard) guard.emplace(source, target, anchors, sv, static_cast<float>(0.5 * radius));
      const int first_pass = guard ? 0 : 1;
      int best = -1;
      float best_cost = std::numeric_limits<float>::max();
      for (int pass = first_pass; pass < 3 && best < 0; ++pass) {
        for (size_t j = 0; j < pool.size(); ++j) {
          if (pass < 2 && target.sample_field(parent->target_sample, pool[j]) > window) continue;
          if (pass == 0 && !guard->accepts(target.sample_vertex(pool[j]))) continue;
          const float cost = anchored_distortion(source_distances.data(), distances.pool_row(j), anchor_count, -1,
                                                 options.trim_fraction, best_cost, scratch);
          if (cost < best_cost) best_cost = cost, best = pool[j];
        }
      }
      tracked.pairs.push_back({s, best, best_cost});
      matched[s] = 1;
    }
    reassign_pairs(source, target, pool, radius, options, tracked.pairs);
  }
  refine_to_vertices(source, target, options, tracked.pairs);
  tracked.diso = sample_map_diso(source, target, tracked.pairs);
  tracked.orientation = orientation_agreement(source, target, tracked.pairs);
  return tracked;
}

}  // namespace isocorr
