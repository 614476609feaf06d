#include "part_growth.h"

#include <algorithm>
#include <cmath>

#include "isocorr/geodesic/fast_marching.h"
#include "isocorr/matching/orientation.h"

namespace isocorr {
namespace {

// Terms of a sample's cost above this quantile are ignored: robust to a few misplaced pairs.
constexpr double kTrimmedShare = 0.2;
// A sample is matched only when at least this share of its distances to the pairs matched
// before it are exact. The rest are upper bounds, which any image nearer than them meets at
// no cost: a sample on the rim (all its distances bounds: the cut lies between it and every
// other point) lands anywhere at cost 0 and misleads the samples matched after it (TOSCA
// hi-res cat0's front half: rim samples sent half a diameter off, then its other samples
// 0.1-0.4). The dense map places the rim from the pairs inside. Measured on the part
// benchmark's development cuts: 31/36 right either way, Kim error of the right ones 0.049 ->
// 0.038; a band of kRimBand left out instead: 30/36.
constexpr double kMinExactShare = 0.5;
// A sample's image lies within this many times its distance to its parent, around the
// parent's image (the tracker's window_factor).
constexpr float kWindowFactor = 2.0f;

// The cost of a sample's image in the growth: the mean of its exact terms, the largest
// kTrimmedShare of them left out, and of its bound terms (distances the cut may have
// lengthened), all kept. A bound term is 0 unless the image lies farther than the bound
// allows, so trimming it with the rest would drop the exact terms' evidence first and leave
// the bounds' zeros: a sample near the rim then matched almost free (TOSCA hi-res dog0's
// 50% ball: its true extremity map grew samples near the rim 0.2-0.46 of the diameter off).
// Measured on the part benchmark: 36 development cuts 31 right either way (Kim error 0.038
// -> 0.037); held out faust_reg6890 + faust_remeshed_lps 22 -> 23 of 24, TOSCA hi-res 13 ->
// 16 of 20, kids 2 -> 3 of 4.
float trimmed_mean_with_bounds(std::vector<float>& exact_terms, double bound_sum, int bounds) {
  if (exact_terms.empty()) return bounds ? static_cast<float>(bound_sum / bounds) : kUnreached;
  const size_t kept =
      std::max<size_t>(1, static_cast<size_t>(std::ceil(exact_terms.size() * (1 - kTrimmedShare))));
  std::nth_element(exact_terms.begin(), exact_terms.begin() + (kept - 1), exact_terms.end());
  double sum = bound_sum;
  for (size_t i = 0; i < kept; ++i) sum += exact_terms[i];
  return static_cast<float>(sum / (kept + bounds));
}

}  // namespace

float trimmed_mean(std::vector<float>& terms) { return trimmed_mean_with_bounds(terms, 0, 0); }

namespace {

// Calls visit(source distance, raw target distance, source exact, target exact) for every
// pair of pairs of a sample map.
template <class Visit>
void for_each_pair_of_pairs(const PartGeometry& part, const std::vector<SamplePair>& pairs, Visit visit) {
  const PreprocessedShape& target = part.target;
  for (size_t i = 0; i < pairs.size(); ++i)
    for (size_t j = i + 1; j < pairs.size(); ++j) {
      const int sv = part.shape.sample_vertex(pairs[j].source_sample);
      const float gs = part.distance(pairs[i].source_sample, sv);
      const int ta = target.sample_vertex(pairs[i].target_sample), tb = target.sample_vertex(pairs[j].target_sample);
      const double gt = target.field(pairs[i].target_sample, tb) * target.diameter();
      visit(gs, gt, part.exact(pairs[i].source_sample, sv, gs), part.target_exact(ta, tb, static_cast<float>(gt)));
    }
}

// Scale normalisation from trusted matches: the median source/target distance ratio over
// the exact distances between matched samples (`fallback` when there are none).
double scale_from_exact_pairs(const PartGeometry& part, const std::vector<SamplePair>& pairs, double fallback) {
  std::vector<double> ratios;
  for_each_pair_of_pairs(part, pairs, [&](float gs, double gt, bool exact, bool target_exact) {
    if (gt > 0 && exact && target_exact) ratios.push_back(gs / gt);
  });
  if (ratios.empty()) return fallback;
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  return ratios[ratios.size() / 2];
}

// A grown map's distortion: the mean mismatch over all its pairs of pairs, untrimmed, at
// scale kappa (fraction of the part's diameter). The cost each sample was matched with is
// no measure of the map: it is trimmed and sees only earlier pairs, so a map grown from
// wrong extremities trims them away and looks as consistent as the right one.
double map_distortion(const PartGeometry& part, const std::vector<SamplePair>& pairs, double scale) {
  double sum = 0;
  long count = 0;
  for_each_pair_of_pairs(part, pairs, [&](float gs, double gt, bool exact, bool target_exact) {
    sum += mismatch(gs, static_cast<float>(gt * scale), exact, target_exact);
    ++count;
  });
  return count ? sum / count / part.shape.diameter() : 0.0;
}

}  // namespace

TrackedMap grow_sample_map(const PartGeometry& part, const ExtremityMap& start, int rank, int last_step,
                           double& grown_scale, const JobControl& control) {
  const PreprocessedShape& source = part.shape;
  const PreprocessedShape& target = part.target;
  const float scale = static_cast<float>(start.scale);
  const float target_diameter = static_cast<float>(target.diameter());
  TrackedMap tracked;
  tracked.level0_rank = rank;
  tracked.level0_diso = start.distortion;
  std::vector<char> matched(source.num_samples(), 0);
  for (size_t i = 0; i < start.source_samples.size(); ++i) {
    tracked.pairs.push_back({start.source_samples[i], start.target_samples[i], 0.0f, -1});
    matched[start.source_samples[i]] = 1;
  }
  std::vector<float> terms, gs;
  std::vector<char> exact;
  for (int s = 0; s < source.num_samples(); ++s) {
    if (matched[s] || source.sample_step(s) > last_step) continue;
    control.check_cancelled();
    const int sv = source.sample_vertex(s);
    // The source side of every term, the same for each image tried.
    const size_t count = tracked.pairs.size();
    gs.resize(count);
    exact.resize(count);
    int exact_terms = 0;
    for (size_t a = 0; a < count; ++a) {
      gs[a] = part.distance(tracked.pairs[a].source_sample, sv);
      exact[a] = part.exact(tracked.pairs[a].source_sample, sv, gs[a]);
      exact_terms += exact[a];
    }
    if (exact_terms < kMinExactShare * count) continue;
    // As in tracking: a new pair must keep the handedness of the pairs near it, or the
    // front of a body drifts onto its back, which geodesics to the extremities cannot tell.
    const HandednessGuard guard(source, target, tracked.pairs, sv, 0.05f);
    // As in tracking, the image is sought near the image of the nearest matched sample
    // (the parent), within twice their distance: a limb's samples cannot jump to another limb.
    const SamplePair* parent = &tracked.pairs.front();
    for (const SamplePair& p : tracked.pairs)
      if (source.field(p.source_sample, sv) < source.field(parent->source_sample, sv)) parent = &p;
    const float window = kWindowFactor * part.distance(parent->source_sample, sv) / (target_diameter * scale);
    float best = kUnreached;
    int best_target = -1;
    for (int t = 0; t < target.num_samples(); ++t) {
      const int tv = target.sample_vertex(t);
      if (target.field(parent->target_sample, tv) > window) continue;
      terms.clear();
      double bound_sum = 0;
      int bounds = 0;
      for (size_t a = 0; a < count; ++a) {
        const SamplePair& p = tracked.pairs[a];
        const float gt = target.field(p.target_sample, tv) * target_diameter;
        const float term =
            mismatch(gs[a], gt * scale, exact[a], part.target_exact(target.sample_vertex(p.target_sample), tv, gt));
        if (exact[a]) terms.push_back(term);
        else bound_sum += term, ++bounds;
      }
      const float cost = trimmed_mean_with_bounds(terms, bound_sum, bounds);
      if (cost < best && guard.accepts(tv)) best = cost, best_target = t;
    }
    if (best_target < 0) continue;
    tracked.pairs.push_back({s, best_target, best / static_cast<float>(source.diameter()), -1});
  }
  tracked.orientation = orientation_agreement(source, target, tracked.pairs);
  grown_scale = scale_from_exact_pairs(part, tracked.pairs, start.scale);
  tracked.diso = map_distortion(part, tracked.pairs, grown_scale);
  return tracked;
}

}  // namespace isocorr
