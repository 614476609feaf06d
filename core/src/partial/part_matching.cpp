#include "isocorr/partial/part_matching.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <limits>
#include <map>
#include <queue>

#include "isocorr/matching/orientation.h"
#include "isocorr/matching/surface_descent.h"
#include "isocorr/partial/partial_refinement.h"
#include "isocorr/refinement/dense_choice.h"
#include "isocorr/refinement/rigidity_polish.h"
#include "isocorr/util/error.h"
#include "isocorr/util/parallel.h"
#include "part_geometry.h"
#include "ravac.h"

namespace isocorr {
namespace {

// Terms of a sample's cost above this quantile are ignored: robust to a few misplaced pairs.
constexpr double kTrimmedShare = 0.2;
// Dense anchors weigh 1 / (distance + kLocality): near pairs count more (as the C2F dense level).
constexpr double kLocality = 0.05;
// A target vertex is covered by the part's image when an image lies within this many
// mean edge lengths of it.
constexpr double kCoverEdges = 2.5;
// Near-isometric meshes differ in area by a few per cent: the area bound on kappa allows it.
constexpr double kAreaSlack = 0.95;
// Target samples offered when the level-0 ones cannot be right: the first half-levels'
// (and the target's extremities: search_targets).
constexpr int kFinerTargets = 20;
// The least extremity-map distortion beyond which none of the level-0 maps is taken as
// consistent. Measured on the part benchmark's 36 development cuts: 0.00-0.02 where the
// target's level 0 holds the part's tips, 0.09-0.20 on the cats' front halves, where it
// does not.
constexpr double kConsistentExtremities = 0.05;
// Extremity maps screened by matching the first levels' samples (schedule steps <= 2).
constexpr int kScreenedMaps = 1000;
constexpr int kScreenLastStep = 2;
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
// Fields on the target per dense map weighed by measure_part_maps (as the complete pipeline's
// dense choice: 16 spread samples against all give a stable mean).
constexpr int kPartEvidenceSources = 16;
// A part's image covers about the part's own area, scaled to the target (its share of the
// target's area is area(part) / (kappa^2 area(target))). A map that covers much less folds
// the part onto a smaller region: not an isometry. Measured on the benchmark's cuts (lab,
// the part search's picks against ground truth): right maps cover 0.89-1.10 of that, wrong
// ones 0.54-0.78 (they pile a half body onto one side).
constexpr double kMinCoveredShare = 0.8;
// The same after the rigidity polish, which spreads a right map over the part's image and
// leaves a fold folded. Measured on the benchmark's cuts (six finalists each): right maps
// cover 0.72-1.01, folding ones 0.35-0.63.
constexpr double kMinCoveredShareFinished = 0.6;
// Candidates finished and compared: the least curvature disagreement among the rough
// upright maps. On the benchmark's 22 cuts with a right candidate, the first right one was
// the rough maps' best on 16, among their best 6 on 20 (SCAPE 000 -> 003's plane cut: 23rd).
constexpr int kFinalists = 6;
// A rough candidate's orientation is measured on the faces around every this-many-th
// spectral sample (farthest-point order: spread over the part).
constexpr int kOrientationSampleStride = 4;

// The widened targets: the first `count` samples and, for every extremity of the target,
// the sample nearest it. Level 0 keeps only one extremity within its radius (0.2 of the
// diameter), so a cat whose front paws are close in its pose has one of them outside level
// 0 (TOSCA hi-res cat1: the 22nd sample; the front half's least extremity distortion 0.19
// without it, 0.003 with it), and an extremity within a finer radius of a sample is no
// sample itself (5K cat1: 0.013 from the 252nd); the part's extremities, away from the cut,
// are tips of the whole and map to those. Not offered at level 0 already: a dog has 14
// extremities (ears and toes), and the distractors cost it the cuts level 0 gets right.
std::vector<int> search_targets(const PreprocessedShape& target, int count) {
  std::vector<int> targets(count);
  std::iota(targets.begin(), targets.end(), 0);
  for (const int e : target.saliency().extremities) {
    int nearest = 0;
    for (int j = 1; j < target.num_samples(); ++j)
      if (target.field(j, e) < target.field(nearest, e)) nearest = j;
    if (std::find(targets.begin(), targets.end(), nearest) == targets.end()) targets.push_back(nearest);
  }
  return targets;
}

// Step 1: every injective map of the source's points to the target samples `targets`, the
// `keep` of least scale-invariant distortion first; maps with kappa below `min_scale` are
// dropped. The assignments are split by the first point's target, one worker each, each
// keeping its own best `keep`: a widened search (22P5 = 3.2M maps) never holds them all.
std::vector<ExtremityMap> rank_extremity_maps(const PartGeometry& part, const std::vector<int>& source_samples,
                                              const std::vector<int>& targets, double min_scale, int keep,
                                              int threads) {
  const int m = static_cast<int>(source_samples.size());
  const int target_count = static_cast<int>(targets.size());
  const PreprocessedShape& source = part.shape;
  const PreprocessedShape& target = part.target;
  std::vector<std::vector<double>> gs(m, std::vector<double>(m));
  const Eigen::MatrixXd gt = sample_distances(target, targets) * target.diameter();
  std::vector<std::vector<char>> exact(m, std::vector<char>(m));
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      const int vj = source.sample_vertex(source_samples[j]);
      const float d = part.distance(source_samples[i], vj);
      gs[i][j] = d;
      exact[i][j] = part.exact(source_samples[i], vj, d);
    }
  std::vector<std::vector<char>> target_exact(target_count, std::vector<char>(target_count));
  for (int i = 0; i < target_count; ++i)
    for (int j = 0; j < target_count; ++j)
      target_exact[i][j] = part.target_exact(target.sample_vertex(targets[i]), target.sample_vertex(targets[j]),
                                             static_cast<float>(gt(i, j)));

  // A map's place: its distortion, then the order of enumeration (lexicographic in the
  // targets: the first target, then the order within its worker), so that ties come out as
  // a stable sort of all maps would leave them.
  struct Ranked {
    double distortion;
    long long order;  // within the worker of target_of[0]
    std::vector<int> target_of;
    double scale;
    bool operator<(const Ranked& o) const {
      if (distortion != o.distortion) return distortion < o.distortion;
      return target_of[0] != o.target_of[0] ? target_of[0] < o.target_of[0] : order < o.order;
    }
  };
  std::vector<std::vector<Ranked>> best_of(target_count);
  parallel_for(target_count, threads, [&](int first, int) {
    std::vector<Ranked>& heap = best_of[first];  // max-heap by rank: its top is the worst kept
    std::vector<int> target_of(m);
    std::vector<char> used(target_count, 0);
    long long order = 0;
    used[first] = 1, target_of[0] = first;
    std::function<void(int)> assign = [&](int depth) {
      if (depth == m) {
        double scale = 1;
        const double distortion = scale_invariant_distortion(gs, gt, exact, target_exact, target_of, scale);
        ++order;
        if (scale < min_scale) return;
        if (static_cast<int>(heap.size()) == keep) {
          const Ranked& worst = heap.front();  // same first target: the order breaks ties
          if (distortion > worst.distortion || (distortion == worst.distortion && order > worst.order)) return;
          std::pop_heap(heap.begin(), heap.end());
          heap.pop_back();
        }
        heap.push_back({distortion, order, target_of, scale});
        std::push_heap(heap.begin(), heap.end());
        return;
      }
      for (int t = 0; t < target_count; ++t) {
        if (used[t]) continue;
        used[t] = 1, target_of[depth] = t;
        assign(depth + 1);
        used[t] = 0;
      }
    };
    assign(1);
  });
  std::vector<Ranked> all;
  for (auto& heap : best_of)
    for (Ranked& r : heap) all.push_back(std::move(r));
  std::sort(all.begin(), all.end());
  if (static_cast<int>(all.size()) > keep) all.resize(keep);
  std::vector<ExtremityMap> maps;
  for (Ranked& r : all) {
    for (int& t : r.target_of) t = targets[t];
    maps.push_back({source_samples, std::move(r.target_of), r.distortion, r.scale});
  }
  return maps;
}

// Trimmed mean of per-anchor mismatches: the largest kTrimmedShare are left out.
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

// Trimmed mean of per-anchor mismatches: the largest kTrimmedShare are left out.
float trimmed_mean(std::vector<float>& terms) { return trimmed_mean_with_bounds(terms, 0, 0); }

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

// Step 3: source samples of schedule steps up to `last_step` matched coarse to fine to
// target samples, each against every pair matched before it.
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

// Order in which source vertices are visited: breadth first from the first extremity (every
// candidate's first pair), so each vertex's descent starts at the image of a neighbour; each
// vertex's parent is the neighbour it was reached from (-1 for the first).
struct VisitOrder {
  std::vector<int> order;
  std::vector<int> parent;
};

VisitOrder breadth_first_order(const PreprocessedShape& shape, int start) {
  const MeshTopology& topology = shape.geodesics().topology();
  VisitOrder visit;
  visit.parent.assign(shape.mesh().num_vertices(), -1);
  std::vector<char> seen(shape.mesh().num_vertices(), 0);
  visit.order.reserve(seen.size());
  std::queue<int> queue;
  queue.push(start);
  seen[start] = 1;
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop();
    visit.order.push_back(v);
    for (const int* u = topology.neighbours_begin(v); u != topology.neighbours_end(v); ++u)
      if (!seen[*u]) seen[*u] = 1, visit.parent[*u] = v, queue.push(*u);
  }
  return visit;
}

// The vertices a rough candidate's map is made on when its finalists are finished (and its
// dense map made then): the spectral samples, where its curvature is compared, and the
// faces around every kOrientationSampleStride-th of them, where its orientation is (a
// 28K-vertex part: about 5000 of its vertices).
std::vector<char> rough_map_vertices(const PreprocessedShape& source) {
  const MeshTopology& topology = source.geodesics().topology();
  std::vector<char> wanted(source.mesh().num_vertices(), 0);
  const std::vector<int>& samples = source.spectral_samples();
  for (size_t i = 0; i < samples.size(); ++i) {
    wanted[samples[i]] = 1;
    if (i % kOrientationSampleStride == 0)
      for (const int* u = topology.neighbours_begin(samples[i]); u != topology.neighbours_end(samples[i]); ++u)
        wanted[*u] = 1;
  }
  return wanted;
}

// A rough map's vertices left out (-1) take the image of their visit parent, so that the
// candidate's map kept for the report is defined everywhere.
void fill_from_parents(const VisitOrder& visit, int fallback, std::vector<int>& forward) {
  for (const int v : visit.order)
    if (forward[v] < 0 && visit.parent[v] >= 0) forward[v] = forward[visit.parent[v]];
  for (int& t : forward)
    if (t < 0) t = fallback;  // unreachable from the first vertex, as in dense_part_map
}

// The target side of the dense anchors: each pair's image and its distance field, either
// the target's sample fields (cheap: for comparing candidates) or fields computed from
// vertex-accurate images (for the chosen map).
struct TargetAnchors {
  std::vector<int> vertex;
  std::vector<const float*> rows;  // distance to every target vertex, times row_scale = raw
  float row_scale = 1;
  std::vector<std::vector<float>> computed_fields;
};

TargetAnchors sample_anchors(const PreprocessedShape& target, const std::vector<SamplePair>& pairs) {
  TargetAnchors anchors;
  for (const SamplePair& p : pairs) {
    anchors.vertex.push_back(target.sample_vertex(p.target_sample));
    anchors.rows.push_back(target.field_row(p.target_sample));
  }
  anchors.row_scale = static_cast<float>(target.diameter());
  return anchors;
}

// Each pair's image moved from its target sample to the vertex that best agrees with the
// other pairs (a sample spacing is about 4% of the diameter: too coarse for the dense map),
// then a geodesic field from each moved image.
TargetAnchors vertex_accurate_anchors(const PartGeometry& part, const std::vector<SamplePair>& pairs, double scale,
                                      int threads, const JobControl& control) {
  const PreprocessedShape& target = part.target;
  TargetAnchors anchors;
  const int count = static_cast<int>(pairs.size());
  anchors.vertex.resize(count);
  anchors.computed_fields.resize(count);
  const float target_diameter = static_cast<float>(target.diameter());
  const float scale_f = static_cast<float>(scale);
  parallel_for(count, threads, [&](int q, int) {
    control.check_cancelled();
    const int sv = part.shape.sample_vertex(pairs[q].source_sample);
    std::vector<float> gs(count);
    std::vector<char> exact(count);
    for (int p = 0; p < count; ++p) {
      gs[p] = part.distance(pairs[p].source_sample, sv);
      exact[p] = part.exact(pairs[p].source_sample, sv, gs[p]);
    }
    std::vector<float> terms;
    auto cost = [&](int t) {
      terms.clear();
      for (int p = 0; p < count; ++p) {
        if (p == q) continue;
        const float gt = target.field(pairs[p].target_sample, t) * target_diameter;
        terms.push_back(mismatch(gs[p], gt * scale_f, exact[p],
                                 part.target_exact(target.sample_vertex(pairs[p].target_sample), t, gt)));
      }
      return trimmed_mean(terms);
    };
    float best = 0;
    anchors.vertex[q] = descend_to_minimum<CostPrice::kDear>(
        target.geodesics().topology(), target.sample_vertex(pairs[q].target_sample), cost, best);
    anchors.computed_fields[q] = target.geodesics().distance_field(anchors.vertex[q]);
  });
  for (const auto& field : anchors.computed_fields) anchors.rows.push_back(field.data());
  anchors.row_scale = 1;
  return anchors;
}

// Step 4: every source vertex in `visit` order, or only those `wanted` (when not empty; the
// rest -1), by descent of the anchors' weighted mismatch on the target (the forward map only).
DenseMap dense_part_map(const PartGeometry& part, const TrackedMap& chosen, const TargetAnchors& anchors, double scale,
                        const VisitOrder& visit, const std::vector<char>& wanted, const JobControl& control) {
  const PreprocessedShape& source = part.shape;
  const PreprocessedShape& target = part.target;
  const int source_vertices = source.mesh().num_vertices();
  const float scale_f = static_cast<float>(scale);
  const float source_diameter = static_cast<float>(source.diameter());
  const auto& pairs = chosen.pairs;
  DenseMap dense;
  dense.forward.assign(source_vertices, -1);
  dense.forward_diso.assign(source_vertices, 0.0f);

  // Per pair, what does not depend on the vertex: this loop runs once per source vertex
  // and candidate, its cost function some 25 times per vertex (64 candidates of a 28K
  // part: most of a part match's time).
  const size_t count = pairs.size();
  std::vector<const float*> source_rows(count);
  std::vector<float> sample_boundary(count), anchor_boundary(count);
  for (size_t a = 0; a < count; ++a) {
    source_rows[a] = source.field_row(pairs[a].source_sample);
    sample_boundary[a] = part.boundary_distance[source.sample_vertex(pairs[a].source_sample)];
    anchor_boundary[a] = part.target_boundary_distance[anchors.vertex[a]];
  }
  std::vector<float> gs(count), weight(count);
  std::vector<char> exact(count);
  const MeshTopology& source_topology = source.geodesics().topology();
  const MeshTopology& target_topology = target.geodesics().topology();
  const std::vector<int>& order = visit.order;
  for (size_t k = 0; k < order.size(); ++k) {
    if (k % 4096 == 0) control.check_cancelled();
    const int v = order[k];
    if (!wanted.empty() && !wanted[v]) continue;
    const float vertex_boundary = part.boundary_distance[v];
    double total = 0;
    for (size_t a = 0; a < count; ++a) {
      gs[a] = source_rows[a][v] * source_diameter;  // part.distance
      exact[a] = gs[a] < sample_boundary[a] + vertex_boundary;  // part.exact
      weight[a] = 1.0f / (gs[a] / source_diameter + static_cast<float>(kLocality));
      total += weight[a];
    }
    auto cost = [&](int t) {
      const float target_boundary = part.target_boundary_distance[t];
      double sum = 0;
      for (size_t a = 0; a < count; ++a) {
        const float gt = anchors.rows[a][t] * anchors.row_scale;
        sum += weight[a] * mismatch(gs[a], gt * scale_f, exact[a], gt < anchor_boundary[a] + target_boundary);
      }
      return static_cast<float>(sum / total);
    };
    // Start at a visited neighbour's image, else at the nearest visited ancestor's, else at
    // the nearest anchor's image.
    int start = -1;
    for (const int* u = source_topology.neighbours_begin(v); u != source_topology.neighbours_end(v) && start < 0; ++u)
      start = dense.forward[*u];
    for (int u = visit.parent[v]; u >= 0 && start < 0; u = visit.parent[u]) start = dense.forward[u];
    if (start < 0) {
      size_t nearest = 0;
      for (size_t a = 1; a < pairs.size(); ++a)
        if (gs[a] < gs[nearest]) nearest = a;
      start = anchors.vertex[nearest];
    }
    float best = 0;
    dense.forward[v] = descend_to_minimum<CostPrice::kDear>(target_topology, start, cost, best);
    dense.forward_diso[v] = best / source_diameter;
  }
  for (int v = 0; v < source_vertices; ++v)  // unreachable from the first vertex: cannot happen on a cleaned mesh
    if (dense.forward[v] < 0 && (wanted.empty() || wanted[v]))
      dense.forward[v] = target.sample_vertex(pairs.front().target_sample);
  return dense;
}

// Steps 1 and 2 of the part search (the source is a part of the target): the candidates,
// with kappa from their screened maps. `ranks` gets each one's rank by extremity distortion.
std::vector<ExtremityMap> part_search_candidates(const PartGeometry& part, const MatchSettings& settings, int threads,
                                                 MatchResult& result, std::vector<int>& ranks,
                                                 const JobControl& control) {
  const PreprocessedShape& source = part.shape;
  const PreprocessedShape& target = part.target;
  bool offer_finer_targets = false;
  const std::vector<int> extremities =
      search_samples(source, part.boundary_distance, static_cast<float>(kRimBand * source.diameter()),
                     settings.part_extremities, offer_finer_targets);
  // Targets: the level-0 samples (extremities first), or the samples of the first
  // half-levels when the part's points are not all extremities.
  const int finer_count = std::min(target.num_samples(), kFinerTargets);
  std::vector<int> targets(offer_finer_targets ? finer_count : target.num_level0_samples());
  std::iota(targets.begin(), targets.end(), 0);
  if (targets.size() < extremities.size())
    throw InputError("the target has fewer level-0 samples (" + std::to_string(targets.size()) +
                     ") than the part's extremities (" + std::to_string(extremities.size()) + ")");
  // The part is a piece of the target scaled by kappa, so its area is at most kappa^2 times
  // the target's: a smaller kappa cannot be right.
  const double min_scale = kAreaSlack * std::sqrt(source.area() / target.area());
  std::vector<ExtremityMap> all_maps =
      rank_extremity_maps(part, extremities, targets, min_scale, kScreenedMaps, threads);
  // No map of the extremities to the target's level 0 is consistent: the part has tips the
  // target's level 0 lacks (a cat's front half finds its ears and nose apart, where the
  // whole cat has one sample on its head), so the finer targets and the target's
  // extremities are offered too.
  if (!all_maps.empty() && all_maps.front().distortion > kConsistentExtremities &&
      target.num_level0_samples() < finer_count && !offer_finer_targets)
    all_maps =
        rank_extremity_maps(part, extremities, search_targets(target, finer_count), min_scale, kScreenedMaps, threads);
  if (all_maps.empty())
    throw InputError("no extremity map is consistent with the part's area: is the source a part of the target?");
  for (const auto& map : all_maps) result.diagnostics.level0.maps.push_back({map.target_samples, map.distortion});

  // Screening: with few extremities, or distances all lengthened by the cut, many
  // extremity maps are equally consistent; matching the first levels' samples (steps <= 2)
  // against each tells them apart at a fraction of a full growth's cost.
  control.report({"part-screening", 1, 2, 0.1});
  std::vector<TrackedMap> screened(all_maps.size());
  std::vector<double> screened_scale(all_maps.size());
  parallel_for(static_cast<int>(all_maps.size()), threads, [&](int i, int) {
    screened[i] = grow_sample_map(part, all_maps[i], i, kScreenLastStep, screened_scale[i], control);
  });
  // Candidates: half the best by extremity distortion (right when the extremities pin the
  // map down), half the best screened (right when they tie), each map once.
  std::vector<int> by_screening(all_maps.size());
  std::iota(by_screening.begin(), by_screening.end(), 0);
  std::stable_sort(by_screening.begin(), by_screening.end(),
                   [&](int a, int b) { return screened[a].diso < screened[b].diso; });
  ranks.clear();
  const size_t wanted = std::min<size_t>(all_maps.size(), settings.part_candidates);
  for (size_t k = 0; ranks.size() < wanted; ++k) {
    for (int i : {static_cast<int>(k), by_screening[k]})  // all_maps is sorted by D already
      if (ranks.size() < wanted && std::find(ranks.begin(), ranks.end(), i) == ranks.end()) ranks.push_back(i);
  }
  std::vector<ExtremityMap> maps;
  for (int i : ranks) {
    maps.push_back(all_maps[i]);
    maps.back().scale = screened_scale[i];  // kappa from the screened map's exact distances
  }
  return maps;
}

// The share of the part's expected image area (area(part) / kappa^2) that its dense map
// covers on the target (kCoverEdges around each image, as the reverse map marks it); fills
// map's reverse map.
double covered_share(const PreprocessedShape& source, const PreprocessedShape& target,
                     const std::vector<double>& target_vertex_areas, double scale, DenseMap& map) {
  add_part_reverse_map(source, target, scale, map);
  const double expected_share = source.area() / (scale * scale * target.area());
  return expected_share > 0 ? matched_area_share(target_vertex_areas, map.reverse) / expected_share : 0;
}

// The `count` upright maps (orientation at least `threshold`) of least curvature
// disagreement; when none is upright, the `count` of least curvature.
std::vector<int> part_finalists(const std::vector<TrackedMap>& tracked, const std::vector<double>& curvature,
                                double threshold, int count) {
  std::vector<int> order(tracked.size());
  std::iota(order.begin(), order.end(), 0);
  auto upright = [&](int i) { return tracked[i].orientation >= threshold; };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return upright(a) != upright(b) ? upright(a) : curvature[a] < curvature[b];
  });
  const bool any_upright = !order.empty() && upright(order.front());
  std::vector<int> finalists;
  for (int i : order)
    if (static_cast<int>(finalists.size()) < count && (upright(i) || !any_upright)) finalists.push_back(i);
  return finalists;
}

// The complete pipeline's last stage on a part's forward map, at the part's scale kappa.
void polish_part_map(const PreprocessedShape& source, const PreprocessedShape& target, RigidityOptions options,
                     double scale, int threads, DenseMap& map, const JobControl& control) {
  SpectralMap polished;  // no reverse_image: a part's reverse map is made from the forward one
  polished.image = std::move(map.forward);
  options.threads = threads;
  RigidityPolish(source, target, options, 1.0 / scale).apply(polished, control);
  map.forward = std::move(polished.image);
  map.forward_diso = std::move(polished.residual);
}

}  // namespace

DenseMap match_part(const PreprocessedShape& source, const PreprocessedShape& target, const MatchSettings& settings,
                    MatchResult& result, const JobControl& control) {
  StageClock clock(result.timings.stages);
  const PartGeometry part(source, target);
  const int threads = resolve_thread_count(settings.threads);

  control.report({"part-extremities", 0, 2, 0.0});
  std::vector<int> ranks;
  std::vector<ExtremityMap> maps;
  if (settings.method == MatchMethod::kRavac) {
    maps = ravac_extremity_maps(part, settings.part_candidates, threads, result.messages.notes, control);
    for (size_t i = 0; i < maps.size(); ++i) {
      ranks.push_back(static_cast<int>(i));
      result.diagnostics.level0.maps.push_back({maps[i].target_samples, maps[i].distortion});
    }
    clock.finish("ravac");
  } else {
    maps = part_search_candidates(part, settings, threads, result, ranks, control);
    clock.finish("part-candidates");  // extremity maps and their screening
  }

  control.report({"part-tracking", 1, 2, 0.3});
  result.diagnostics.tracking.maps.resize(maps.size());
  std::vector<double> scales(maps.size());
  std::atomic<int> done{0};
  const int last_step = 2 * source.options().decision_level;
  parallel_for(static_cast<int>(maps.size()), threads, [&](int i, int) {
    result.diagnostics.tracking.maps[i] = grow_sample_map(part, maps[i], ranks[i], last_step, scales[i], control);
    control.report({"part-tracking", 1, 2, 0.3 + 0.4 * (++done) / maps.size()});
  });
  clock.finish("part-tracking");

  // Each candidate extended to the part's vertices: a mirrored map reverses most faces there
  // (sample triangles are too coarse to show it), so dense orientation drops mirrors; the
  // rest compete by curvature.
  control.report({"part-dense", 2, 2, 0.7});
  std::vector<DenseMap> dense(maps.size());
  std::vector<double> curvature(maps.size());
  // Breadth first from each candidate's first pair: one order per distinct first sample (the
  // part search's candidates all share theirs, RAVAC's do not).
  std::map<int, VisitOrder> orders;
  for (const ExtremityMap& map : maps)
    if (!orders.count(map.source_samples.front()))
      orders[map.source_samples.front()] = breadth_first_order(source, source.sample_vertex(map.source_samples.front()));
  auto visit_order = [&](const ExtremityMap& map) -> const VisitOrder& { return orders.at(map.source_samples.front()); };
  auto first_image = [&](int i) { return target.sample_vertex(result.diagnostics.tracking.maps[i].pairs.front().target_sample); };
  std::vector<double> covered(maps.size(), std::numeric_limits<double>::quiet_NaN());
  const std::vector<double> target_vertex_areas = vertex_areas(target.mesh());
  const PartCurvature part_curvature(part, scales, threads);
  // The evidence the choice weighs, of candidate i's dense map (the covered share needs a
  // map on every vertex).
  auto measure = [&](int i, bool with_covered_share) {
    result.diagnostics.tracking.maps[i].orientation = dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(),
                                                                target.normals(), dense[i].forward);
    curvature[i] = part_curvature.disagreement(dense[i].forward, scales[i]);
    if (with_covered_share) covered[i] = covered_share(source, target, target_vertex_areas, scales[i], dense[i]);
  };
  const bool finish = finishes_part_maps(settings);
  // Without finishing, every candidate competes on its dense map. With it, only the
  // finalists do, and the rest need only what picks the finalists: orientation and
  // curvature, on a map made on rough_map_vertices (covered share not measured: NaN).
  // Against all 64 made on every vertex: the same result on every cut of the part benchmark
  // (36 development, 24 held out); partial_holes_derived (isocorr-bench --partial) 23.2-24.0
  // -> 17.9-18.6 s on the 28K cat, 14.0-15.8 -> 11.0-11.8 s on the 16K centaur.
  const std::vector<char> wanted = finish ? rough_map_vertices(source) : std::vector<char>();
  parallel_for(static_cast<int>(maps.size()), threads, [&](int i, int) {
    dense[i] = dense_part_map(part, result.diagnostics.tracking.maps[i], sample_anchors(target, result.diagnostics.tracking.maps[i].pairs), scales[i],
                              visit_order(maps[i]), wanted, control);
    measure(i, !finish);
    if (finish) fill_from_parents(visit_order(maps[i]), first_image(i), dense[i].forward);  // for the report
  });
  // The finalists, made on every vertex and finished, are measured again and compete: a
  // rough map's curvature carries a sample spacing's worth of noise.
  const std::vector<int> finalists = part_finalists(result.diagnostics.tracking.maps, curvature, settings.orientation_threshold,
                                                    finish ? kFinalists : static_cast<int>(maps.size()));
  // Half the winner's iterations: the comparison needs the sample noise taken out, not the
  // slide converged. Against all of them: the same result on 59 of the part benchmark's 60
  // cuts (the 60th wrong either way), partial_holes_derived's 28K cat 27.6 -> 24.5 s (23.8
  // without finalists).
  RigidityOptions finalist_polish = settings.rigidity;
  finalist_polish.iterations = std::max(1, settings.rigidity.iterations / 2);
  // Each finalist's map refined spectrally (partial_refinement.h) before its polish, kept
  // only if it then agrees better in curvature and keeps handedness: a refinement that
  // folds a limb over (SCAPE 000 -> 002's 47% ball: a right map's orientation 0.79 -> 0.35)
  // is dropped, as the rigidity polish could not undo it. Both are compared unpolished.
  auto refine_if_better = [&](int i, int workers, std::vector<int>& forward) {
    ZoomOutOptions options = settings.zoomout;
    options.threads = workers;
    std::vector<int> refined = refine_part_map_spectrally(source, target, scales[i], options, forward, control);
    const double orientation =
        dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(), target.normals(), refined);
    const bool kept = orientation >= settings.orientation_threshold &&
                      part_curvature.disagreement(refined, scales[i]) < part_curvature.disagreement(forward, scales[i]);
    if (kept) forward = std::move(refined);
    return kept;
  };
  std::vector<std::vector<int>> refined_maps(maps.size());  // a finalist's kept refinement, unpolished
  if (finish)
    parallel_for(static_cast<int>(finalists.size()), threads, [&](int k, int) {
      const int i = finalists[k];
      dense[i] = dense_part_map(part, result.diagnostics.tracking.maps[i], sample_anchors(target, result.diagnostics.tracking.maps[i].pairs), scales[i],
                                visit_order(maps[i]), {}, control);
      if (refine_if_better(i, 1, dense[i].forward)) refined_maps[i] = dense[i].forward;
      polish_part_map(source, target, finalist_polish, scales[i], 1, dense[i], control);  // side by side
      measure(i, true);
    });
  // The winner: least curvature disagreement among the finalists that keep handedness. The
  // sample distortion the candidates were grown by cannot judge them (a map grown from wrong
  // extremities trims them away, and one-sided terms near a cut forgive it); curvature is
  // evidence none of them was fitted to. Measured on cuts (isocorr-bench-partial, 16
  // candidates): right on 12 of 36 cuts, against 7 by orientation then sample distortion.
  // Finishing 6 finalists first (64 candidates): 25 -> 26 of 36 (FAUST 000 -> 004's 54%
  // ball: its right rough map covered 0.75 and lost to a turned body at kMinCoveredShare);
  // on the cuts of faust_reg6890 and faust_remeshed_lps 23 of 24 either way.
  // Maps that fold the part onto much less than its own area go only when no other is
  // upright (min_covered).
  const double min_covered = finish ? kMinCoveredShareFinished : kMinCoveredShare;
  auto least_curvature = [&](double covered_at_least) {
    int best = -1;
    for (int i : finalists)
      if (result.diagnostics.tracking.maps[i].orientation >= settings.orientation_threshold && covered[i] >= covered_at_least &&
          (best < 0 || curvature[i] < curvature[best]))
        best = i;
    return best;
  };
  int best = least_curvature(min_covered);
  if (best < 0) best = least_curvature(0);
  result.diagnostics.tracking.chosen = best >= 0 ? best : rank_tracked(result.diagnostics.tracking.maps, settings).front();
  // The candidates' maps are done with: the winner is made again from vertex-accurate anchors.
  for (int i = 0; i < static_cast<int>(maps.size()); ++i) {
    const bool finalist = finish && std::find(finalists.begin(), finalists.end(), i) != finalists.end();
    result.diagnostics.part.candidates.push_back({result.diagnostics.tracking.maps[i].orientation, curvature[i], covered[i], scales[i],
                                      result.diagnostics.tracking.maps[i].diso, maps[i].distortion, finalist, i == result.diagnostics.tracking.chosen,
                                      std::move(dense[i].forward)});
  }
  const TrackedMap& winner = result.diagnostics.tracking.maps[result.diagnostics.tracking.chosen];
  DenseMap chosen;
  if (!refined_maps[result.diagnostics.tracking.chosen].empty()) {
    // Its refined map is already finer than one made from vertex-accurate anchors.
    chosen.forward = std::move(refined_maps[result.diagnostics.tracking.chosen]);
    result.messages.notes.push_back("part search: the chosen map is its finalist's spectral refinement");
  } else {
    const TargetAnchors anchors = vertex_accurate_anchors(part, winner.pairs, scales[result.diagnostics.tracking.chosen], threads, control);
    chosen = dense_part_map(part, winner, anchors, scales[result.diagnostics.tracking.chosen], visit_order(maps[result.diagnostics.tracking.chosen]), {}, control);
    if (finish) {
      const bool refined = refine_if_better(result.diagnostics.tracking.chosen, threads, chosen.forward);
      result.messages.notes.push_back(std::string("part search: the chosen map made from vertex-accurate anchors, its spectral "
                                         "refinement ") +
                             (refined ? "kept" : "dropped (its curvature agreed less, or it lost handedness)"));
    }
  }
  // The complete pipeline's last stage, at the part's scale: the descent leaves each vertex
  // where its anchors' distances agree best, a sample spacing's worth of noise the polish
  // takes out (isocorr-bench-partial: Kim error of right maps 0.052 -> 0.050, and a map
  // compared against the complete pipeline's polished one is compared like for like:
  // faust 002 -> 007's 46% ball now keeps the part search's right map).
  if (finish) polish_part_map(source, target, settings.rigidity, scales[result.diagnostics.tracking.chosen], threads, chosen, control);
  add_part_reverse_map(source, target, scales[result.diagnostics.tracking.chosen], chosen);
  clock.finish("part-dense");
  result.quality.part_scale = scales[result.diagnostics.tracking.chosen];
  return chosen;
}

DenseMap refine_as_part_map(const PreprocessedShape& source, const PreprocessedShape& target,
                            const MatchSettings& settings, double scale, const std::vector<int>& forward,
                            const JobControl& control) {
  const int threads = resolve_thread_count(settings.threads);
  ZoomOutOptions options = settings.zoomout;
  options.threads = threads;
  DenseMap map;
  map.forward = refine_part_map_spectrally(source, target, scale, options, forward, control);
  polish_part_map(source, target, settings.rigidity, scale, threads, map, control);
  return map;
}

// Edge-graph Dijkstra from the images, carrying their source vertices.
void add_part_reverse_map(const PreprocessedShape& source, const PreprocessedShape& target, double scale,
                          DenseMap& dense) {
  const int source_vertices = source.mesh().num_vertices();
  const MeshTopology& target_topology = target.geodesics().topology();
  const TriangleMesh& tm = target.mesh();
  const int target_vertices = tm.num_vertices();
  dense.reverse.assign(target_vertices, -1);
  dense.reverse_diso.assign(target_vertices, kUnreached);
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
  for (int v = 0; v < source_vertices; ++v) {
    const int t = dense.forward[v];
    if (dense.reverse[t] < 0 || dense.forward_diso[v] < dense.forward_diso[dense.reverse[t]]) dense.reverse[t] = v;
    dense.reverse_diso[t] = 0;
  }
  for (int t = 0; t < target_vertices; ++t)
    if (dense.reverse[t] >= 0) heap.push({0.0f, t});
  const float reach = static_cast<float>(kCoverEdges * std::max(target.mean_edge(), source.mean_edge() / scale));
  while (!heap.empty()) {
    const auto [d, t] = heap.top();
    heap.pop();
    if (d > dense.reverse_diso[t]) continue;
    for (const int* u = target_topology.neighbours_begin(t); u != target_topology.neighbours_end(t); ++u) {
      const float nd = d + static_cast<float>((tm.vertices[*u] - tm.vertices[t]).norm());
      if (nd <= reach && nd < dense.reverse_diso[*u]) {
        dense.reverse_diso[*u] = nd;
        dense.reverse[*u] = dense.reverse[t];
        heap.push({nd, *u});
      }
    }
  }
  for (float& d : dense.reverse_diso)
    if (d != kUnreached) d /= static_cast<float>(target.diameter());
}

double matched_area_share(const std::vector<double>& areas, const std::vector<int>& reverse) {
  double matched = 0, total = 0;
  for (size_t t = 0; t < areas.size(); ++t) total += areas[t], matched += reverse[t] >= 0 ? areas[t] : 0;
  return total > 0 ? matched / total : 0;
}

namespace {

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
