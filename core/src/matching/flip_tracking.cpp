#include "isocorr/matching/flip_tracking.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <Eigen/Core>

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

// d_iso(s, t | anchors) from s's distances to the first `count` anchors' sources and t's to
// their images, with the largest `trim` share of the terms left out: a trimmed mean, so
// that a few misplaced anchors or a non-isometric part (a cat's tail) do not decide the
// match. `skip` (or -1) leaves one anchor out entirely.
//
// Most candidates of a sample are far from the best one, and selecting the kept terms
// (std::nth_element) is what costs; they are dismissed by lower bounds instead. For any
// level x >= 0 the kept terms sum to at least sum_i min(term_i, x) - dropped * x (with
// equality where x is the largest kept term): x = the largest term is one cheap pass over
// the terms (estimate()), a ladder of levels below it a tighter second one (value()).
class TrimmedDistortion {
 public:
  TrimmedDistortion(size_t count, int skip, double trim)
      : count_(count), gap_(skip >= 0 && static_cast<size_t>(skip) < count ? static_cast<size_t>(skip) : count) {
    size_ = count - (gap_ < count ? 1 : 0);
    kept_ = std::max<size_t>(1, static_cast<size_t>(std::lround(size_ * (1.0 - trim))));
  }

  struct Estimate {
    double mean = 0;    // of all terms: where the value probably lies
    double lower = 0;   // certainly at most the value
    float largest = 0;  // the largest term
  };
  Estimate estimate(const float* source, const float* target) const {
    if (size_ == 0) return {};
    Estimate estimate;
    double total = 0;
    add_run(source, target, 0, gap_, total, estimate.largest);
    if (gap_ < count_) add_run(source, target, gap_ + 1, count_, total, estimate.largest);
    estimate.mean = total / size_;
    estimate.lower = (total - static_cast<double>(size_ - kept_) * estimate.largest) / kept_;
    return estimate;
  }

  // The trimmed mean, or +infinity where it is certainly above `to_beat` (the best so far).
  float value(const float* source, const float* target, const Estimate& estimate, float to_beat,
              std::vector<float>& scratch) const {
    if (size_ == 0) return 0.f;
    scratch.resize(size_);
    for (size_t i = 0; i < size_; ++i) scratch[i] = term(source, target, i);
    if (kept_ < size_ && clipped_bound(scratch, estimate.largest) > margin(to_beat))
      return std::numeric_limits<float>::infinity();
    if (kept_ < size_) std::nth_element(scratch.begin(), scratch.begin() + kept_, scratch.end());
    double sum = 0;
    for (size_t i = 0; i < kept_; ++i) sum += scratch[i];
    return static_cast<float>(sum / kept_);
  }

  // A candidate whose bound is above this cannot beat `best`: the margin covers the
  // rounding of the sums.
  static double margin(float best) { return 1.0001 * static_cast<double>(best); }

 private:
  // Term i is anchor i's, or anchor i + 1's past the skipped one.
  float term(const float* source, const float* target, size_t i) const {
    const size_t a = i < gap_ ? i : i + 1;
    return std::abs(source[a] - target[a]);
  }

  // The anchors before and after the skipped one are two contiguous runs, summed eight
  // terms at a time in vector registers.
  static void add_run(const float* source, const float* target, size_t begin, size_t end, double& total,
                      float& largest) {
    using Lanes = Eigen::Array<float, 8, 1>;
    Eigen::Array<double, 4, 1> low = Eigen::Array<double, 4, 1>::Zero(), high = low;
    Lanes lanes_largest = Lanes::Zero();
    size_t i = begin;
    for (; i + 8 <= end; i += 8) {
      const Lanes terms = (Eigen::Map<const Lanes>(source + i) - Eigen::Map<const Lanes>(target + i)).abs();
      lanes_largest = lanes_largest.max(terms);
      low += terms.head<4>().cast<double>();
      high += terms.tail<4>().cast<double>();
    }
    total += (low + high).sum();
    largest = std::max(largest, lanes_largest.maxCoeff());
    for (; i < end; ++i) {
      const float t = std::abs(source[i] - target[i]);
      total += t;
      largest = std::max(largest, t);
    }
  }

  // The bound at the levels largest / 2^j, j = 0..7, as a mean of the kept terms: each
  // level costs two vector additions per term (in double: a level far above the kept terms
  // subtracts dropped * level from a sum of about that size).
  double clipped_bound(const std::vector<float>& terms, float largest) const {
    using Levels = Eigen::Array<double, 8, 1>;
    Levels levels;
    for (int j = 0; j < 8; ++j) levels[j] = std::ldexp(static_cast<double>(largest), -j);
    Levels even = Levels::Zero(), odd = Levels::Zero();  // two chains of additions
    size_t i = 0;
    for (; i + 2 <= terms.size(); i += 2) {
      even += levels.min(static_cast<double>(terms[i]));
      odd += levels.min(static_cast<double>(terms[i + 1]));
    }
    if (i < terms.size()) even += levels.min(static_cast<double>(terms[i]));
    const double dropped = static_cast<double>(size_ - kept_);
    return std::max(0.0, (even + odd - dropped * levels).maxCoeff()) / kept_;
  }

  size_t count_, gap_, size_ = 0, kept_ = 1;
};

// The candidate of least trimmed distortion (candidate j's distances to the anchors'
// images are rows.pool_row(j)). Candidates are tried in the order of their mean term, so
// that the first few set a low best and the bounds dismiss most others; the result is the
// same as trying them in turn: the least value, and on a tie the candidate that comes first.
struct Candidate {
  TrimmedDistortion::Estimate estimate;
  int index;  // into the pool
  bool operator<(const Candidate& other) const {
    return estimate.mean < other.estimate.mean || (estimate.mean == other.estimate.mean && index < other.index);
  }
};

struct BestCandidate {
  int index = -1;  // into the pool; -1 where there was no candidate
  float cost = std::numeric_limits<float>::max();
};

BestCandidate least_distortion(const TrimmedDistortion& distortion, const float* source_distances,
                               const AnchorDistances& rows, std::vector<Candidate>& candidates,
                               std::vector<float>& scratch) {
  for (Candidate& c : candidates) c.estimate = distortion.estimate(source_distances, rows.pool_row(c.index));
  std::sort(candidates.begin(), candidates.end());
  BestCandidate best;
  for (const Candidate& c : candidates) {
    if (c.estimate.lower > TrimmedDistortion::margin(best.cost)) continue;
    const float cost = distortion.value(source_distances, rows.pool_row(c.index), c.estimate, best.cost, scratch);
    if (cost < best.cost || (cost == best.cost && c.index < best.index)) best = {c.index, cost};
  }
  return best;
}

// Level-0 samples are only roughly aligned on the two shapes (each mesh is sampled on its
// own), and an early pair that is off by a sample spacing biases every later choice. After
// each level every pair is therefore re-chosen near its current image against all the
// other pairs (leave-one-out), which moves such anchors to where the later ones agree.
void reassign_pairs(const PreprocessedShape& target, const TrackingPlan& plan, const std::vector<int>& pool,
                    double radius, const TrackingOptions& options, std::vector<SamplePair>& pairs) {
  const std::vector<SamplePair> anchors = pairs;
  const size_t anchor_count = std::min(anchors.size(), static_cast<size_t>(options.anchor_cap));
  const AnchorDistances distances(target, anchors, anchor_count, pool);
  std::vector<float> scratch;
  std::vector<Candidate> candidates;
  for (size_t p = 0; p < pairs.size(); ++p) {
    const int current = pairs[p].target_sample;
    candidates.clear();
    for (size_t j = 0; j < pool.size(); ++j) {
      if (target.sample_field(current, pool[j]) > radius) continue;
      candidates.push_back({{}, static_cast<int>(j)});
    }
    const TrimmedDistortion distortion(anchor_count, static_cast<int>(p), options.trim_fraction);
    const BestCandidate best = least_distortion(distortion, plan.distances_to(p), distances, candidates, scratch);
    if (best.index >= 0) pairs[p].target_sample = pool[best.index];
    pairs[p].diso = best.cost;
  }
}

// Target samples are up to half a sample spacing from the true images, which scrambles
// the small triangles of the orientation test. Each pair's image is therefore also
// sought among all target vertices (descent from its sample against the anchors' fields,
// which cover every vertex): no new geodesics are needed.
void refine_to_vertices(const PreprocessedShape& target, const TrackingPlan& plan, const TrackingOptions& options,
                        std::vector<SamplePair>& pairs) {
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
      anchor_distances.push_back(plan.distances_to(p)[a]);
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
    pairs[p].target_vertex = descend_to_minimum<CostPrice::kDear>(topology, target.sample_vertex(pairs[p].target_sample), cost, best);
  }
}

}  // namespace

double sample_map_diso(const PreprocessedShape& source, const PreprocessedShape& target,
                       const std::vector<SamplePair>& pairs) {
  if (pairs.size() < 2) return 0;
  std::vector<int> images(pairs.size());
  for (size_t p = 0; p < pairs.size(); ++p) images[p] = image_vertex(target, pairs[p]);
  // Pair q's target field is read as one row for every other pair (rows are far apart in
  // memory); each pair's sum still runs over q in order.
  std::vector<double> sums(pairs.size(), 0.0);
  for (size_t q = 0; q < pairs.size(); ++q) {
    const float* field = target.field_row(pairs[q].target_sample);
    for (size_t p = 0; p < pairs.size(); ++p)
      if (p != q)
        sums[p] += std::abs(source.sample_field(pairs[q].source_sample, pairs[p].source_sample) - field[images[p]]);
  }
  double total = 0;
  for (size_t p = 0; p < pairs.size(); ++p) total += sums[p] / (pairs.size() - 1);
  return total / pairs.size();
}

TrackingPlan plan_tracking(const PreprocessedShape& source, int level0_count, int levels,
                           const TrackingOptions& options) {
  TrackingPlan plan;
  plan.level0_count = level0_count;
  const double r0 = source.options().level0_radius, shrink = source.options().level_shrink;
  // Only the source samples of the pairs matter here: the targets are the maps'.
  std::vector<SamplePair> matched;
  std::vector<unsigned char> is_matched(source.num_samples(), 0);
  for (int i = 0; i < level0_count; ++i) matched.push_back({i, 0, 0.f}), is_matched[i] = 1;
  for (int level = 1; level <= levels; ++level) {
    const float guard_distance = static_cast<float>(0.5 * r0 * std::pow(shrink, level));
    std::vector<TrackingPlan::Step>& steps = plan.levels.emplace_back();
    for (int s = 0; s < source.num_samples(); ++s) {
      if (is_matched[s] || source.sample_step(s) > 2 * level) continue;
      TrackingPlan::Step& step = steps.emplace_back();
      step.source_sample = s;
      if (options.handedness_guard)
        step.guard = guard_corners(source, matched, source.sample_vertex(s), guard_distance);
    }
    for (const TrackingPlan::Step& step : steps) matched.push_back({step.source_sample, 0, 0.f}), is_matched[step.source_sample] = 1;
  }
  plan.orientation = orientation_triangles(source, matched);
  plan.pair_count = static_cast<int>(matched.size());
  plan.pair_distances.resize(matched.size() * matched.size());
  for (size_t p = 0; p < matched.size(); ++p)
    for (size_t a = 0; a < matched.size(); ++a)
      plan.pair_distances[p * matched.size() + a] = source.sample_field(matched[a].source_sample, matched[p].source_sample);
  return plan;
}

TrackedMap track_map(const PreprocessedShape& source, const PreprocessedShape& target, const TrackingPlan& plan,
                     const Level0Map& map, int rank, const TrackingOptions& options, const JobControl& control) {
  if (static_cast<int>(map.target_of.size()) != plan.level0_count)
    throw std::logic_error("track_map: the plan is for another number of level-0 samples");
  TrackedMap tracked;
  tracked.level0_rank = rank;
  tracked.level0_diso = map.diso;
  for (int i = 0; i < plan.level0_count; ++i) tracked.pairs.push_back({i, map.target_of[i], 0.f});
  const double r0 = source.options().level0_radius, shrink = source.options().level_shrink;
  std::vector<float> scratch;
  std::vector<Candidate> candidates;
  for (int level = 1; level <= static_cast<int>(plan.levels.size()); ++level) {
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
    const TrimmedDistortion distortion(anchor_count, -1, options.trim_fraction);

    for (const TrackingPlan::Step& step : plan.levels[level - 1]) {
      const float* source_distances = plan.distances_to(tracked.pairs.size());  // this step's pair
      // Parent: the nearest sample matched at an earlier level.
      const size_t parent_index =
          static_cast<size_t>(std::min_element(source_distances, source_distances + anchors.size()) - source_distances);
      const SamplePair* parent = &anchors[parent_index];
      const float parent_distance = source_distances[parent_index];
      const double window = options.window_factor * parent_distance + radius;
      // Passes widen the search when nothing qualifies: near the parent's image and
      // keeping handedness, then near the parent's image, then anywhere.
      std::optional<HandednessGuard> guard;
      if (options.handedness_guard) guard.emplace(target, anchors, step.guard);
      const int first_pass = guard ? 0 : 1;
      BestCandidate best;
      for (int pass = first_pass; pass < 3 && best.index < 0; ++pass) {
        candidates.clear();
        for (size_t j = 0; j < pool.size(); ++j) {
          if (pass < 2 && target.sample_field(parent->target_sample, pool[j]) > window) continue;
          if (pass == 0 && !guard->accepts(target.sample_vertex(pool[j]))) continue;
          candidates.push_back({{}, static_cast<int>(j)});
        }
        best = least_distortion(distortion, source_distances, distances, candidates, scratch);
      }
      tracked.pairs.push_back({step.source_sample, best.index >= 0 ? pool[best.index] : -1, best.cost});
    }
    reassign_pairs(target, plan, pool, radius, options, tracked.pairs);
  }
  refine_to_vertices(target, plan, options, tracked.pairs);
  tracked.diso = sample_map_diso(source, target, tracked.pairs);
  tracked.orientation = orientation_agreement(target, tracked.pairs, plan.orientation);
  return tracked;
}

}  // namespace isocorr
