#include "ravac.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "isocorr/util/assignment.h"
#include "isocorr/util/error.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// Points per shape: its level-0 extremities (at most 9 are kept per mesh); when a shape
// has fewer than 3 away from its boundary, the other offers its first samples instead.
constexpr int kPoints = 9;
constexpr int kFinerPoints = 20;
// Each extremity qualifies its best few partners by d~_iso (the paper: "top-ranked").
constexpr int kQualifiedPerPoint = 3;
// A triplet's three distance ratios agree within this factor: near-isometric poses stretch
// geodesics between extremities by well under 10%, a wrong triplet is off by more.
constexpr double kTripletTolerance = 1.25;
// A triplet's region is matched with the source samples of schedule steps <= 2 (the part
// search's screening level) against target samples of steps <= 3 (the M' > M margin).
constexpr int kRegionSourceStep = 2;
constexpr int kRegionTargetStep = 3;
// Votes are exp(-d / sigma) with d relative to the triplet's size. The paper's exp(-d_iso)
// on diameter-normalised distances varies by a few per cent between good and bad triplets,
// which makes the vote a count; sigma = 0.1 of the triplet's size halves a vote at a 7%
// mismatch.
constexpr double kVoteSigma = 0.1;

// One shape's search points and the distances between them.
struct Points {
  std::vector<int> samples;
  std::vector<std::vector<double>> distance;  // raw, symmetrised
  std::vector<std::vector<char>> exact;       // the complete shape's distance (part_geometry.h)
};

Points points_of(const PreprocessedShape& shape, const std::vector<float>& boundary, std::vector<int> samples) {
  Points points;
  points.samples = std::move(samples);
  const int n = static_cast<int>(points.samples.size());
  points.distance.assign(n, std::vector<double>(n, 0));
  points.exact.assign(n, std::vector<char>(n, 1));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int vi = shape.sample_vertex(points.samples[i]), vj = shape.sample_vertex(points.samples[j]);
      const double d = 0.5 * (shape.sample_field(points.samples[i], points.samples[j]) +
                                shape.sample_field(points.samples[j], points.samples[i])) * shape.diameter();
      points.distance[i][j] = d;
      points.exact[i][j] = d < boundary[vi] + boundary[vj];
    }
  return points;
}

// The first `count` samples of a shape (farthest-point order: spread) away from its rim.
std::vector<int> spread_samples(const PreprocessedShape& shape, const std::vector<float>& boundary, int count) {
  const float band = static_cast<float>(kRimBand * shape.diameter());
  std::vector<int> chosen;
  for (int i = 0; i < shape.num_samples() && static_cast<int>(chosen.size()) < count; ++i)
    if (boundary[shape.sample_vertex(i)] >= band) chosen.push_back(i);
  return chosen;
}

// Step 1: d~_iso of the pair (i, j). Scale hypotheses are the ratios of the pair's
// distances to every other pair; at each, every other source point l contributes its best
// relative mismatch over the other target points (injectivity relaxed: a lower bound on
// the least-distortion map of each size), and the cost is the mean over k = 3..5 of the
// mean of the k - 1 smallest contributions.
double ranked_distortion(const Points& s, const Points& t, int i, int j) {
  const int ns = static_cast<int>(s.samples.size()), nt = static_cast<int>(t.samples.size());
  std::vector<double> scales;
  for (int pass = 0; pass < 2 && scales.empty(); ++pass)  // exact on both shapes first
    for (int l = 0; l < ns; ++l)
      for (int m = 0; m < nt; ++m)
        if (l != i && m != j && t.distance[j][m] > 0 && (pass == 1 || (s.exact[i][l] && t.exact[j][m])))
          scales.push_back(s.distance[i][l] / t.distance[j][m]);
  double best = std::numeric_limits<double>::max();
  std::vector<double> contribution;
  for (const double kappa : scales) {
    contribution.clear();
    for (int l = 0; l < ns; ++l) {
      if (l == i) continue;
      double least = std::numeric_limits<double>::max();
      for (int m = 0; m < nt; ++m)
        if (m != j)
          least = std::min<double>(least, mismatch(static_cast<float>(s.distance[i][l]),
                                                   static_cast<float>(kappa * t.distance[j][m]), s.exact[i][l],
                                                   t.exact[j][m]) /
                                              std::max(s.distance[i][l], 1e-12));
      contribution.push_back(least);
    }
    std::sort(contribution.begin(), contribution.end());
    double cost = 0;
    int sizes = 0;
    for (int k = 3; k <= 5 && k - 1 <= static_cast<int>(contribution.size()); ++k, ++sizes) {
      double sum = 0;
      for (int q = 0; q < k - 1; ++q) sum += contribution[q];
      cost += sum / (k - 1);
    }
    if (sizes) best = std::min(best, cost / sizes);
  }
  return best;
}

struct Pair {
  int source, target;  // indices into the Points
};

struct Triplet {
  Pair pairs[3];
  double kappa = 1;
  double vote[3] = {0, 0, 0};  // exp(-d / sigma) earned by each pair
  bool consistent = false;
};

// The triplet's kappa from its three ratios: the mean of those exact on both shapes, which
// must agree within kTripletTolerance; a source distance lengthened by a cut bounds kappa
// from above, a target one from below. False when the ratios contradict each other.
bool triplet_scale(const Points& s, const Points& t, Triplet& triplet) {
  double exact_sum = 0, lowest = std::numeric_limits<double>::max(), highest = 0;
  double upper = std::numeric_limits<double>::max(), lower = 0;
  int exact = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = a + 1; b < 3; ++b) {
      const Pair &p = triplet.pairs[a], &q = triplet.pairs[b];
      const double gt = t.distance[p.target][q.target];
      if (gt <= 0) return false;
      const double r = s.distance[p.source][q.source] / gt;
      const bool se = s.exact[p.source][q.source], te = t.exact[p.target][q.target];
      if (se && te) exact_sum += r, ++exact, lowest = std::min(lowest, r), highest = std::max(highest, r);
      else if (te) upper = std::min(upper, r);
      else if (se) lower = std::max(lower, r);
    }
  if (exact && highest > kTripletTolerance * lowest) return false;
  triplet.kappa = exact ? exact_sum / exact : upper < std::numeric_limits<double>::max() ? upper : lower;
  if (triplet.kappa <= 0) return false;
  return triplet.kappa <= kTripletTolerance * upper && triplet.kappa * kTripletTolerance >= lower;
}

// Step 2 for one triplet: the source samples within half the triplet's longest side of an
// anchor are each matched to the target sample (in the matching region) of least mismatch
// to the three anchors; each pair's vote follows its mean mismatch against those matches.
void vote_triplet(const PartGeometry& geometry, const Points& s, const Points& t, Triplet& triplet) {
  const PreprocessedShape& source = geometry.shape;
  const PreprocessedShape& target = geometry.target;
  int source_anchor[3], target_anchor[3];
  double longest = 0, mean_side = 0;
  for (int a = 0; a < 3; ++a) {
    source_anchor[a] = s.samples[triplet.pairs[a].source];
    target_anchor[a] = t.samples[triplet.pairs[a].target];
    for (int b = a + 1; b < 3; ++b) {
      const double d = s.distance[triplet.pairs[a].source][triplet.pairs[b].source];
      longest = std::max(longest, d), mean_side += d / 3;
    }
  }
  if (mean_side <= 0) return;
  const float source_diameter = static_cast<float>(source.diameter());
  const float target_diameter = static_cast<float>(target.diameter());
  const float kappa = static_cast<float>(triplet.kappa);
  const float reach = static_cast<float>(0.5 * longest);
  std::vector<int> offered;  // target samples near the anchors' images (at the source's scale)
  for (int y = 0; y < target.num_samples(); ++y) {
    if (target.sample_step(y) > kRegionTargetStep) continue;
    const int yv = target.sample_vertex(y);
    float nearest = kUnreached;
    for (int a = 0; a < 3; ++a) nearest = std::min(nearest, target.field(target_anchor[a], yv) * target_diameter);
    if (kappa * nearest <= 1.5f * reach) offered.push_back(y);
  }
  double residual[3] = {0, 0, 0};
  int matched = 0;
  for (int x = 0; x < source.num_samples(); ++x) {
    if (source.sample_step(x) > kRegionSourceStep) continue;
    const int xv = source.sample_vertex(x);
    float gs[3];
    bool se[3];
    float nearest = kUnreached;
    for (int a = 0; a < 3; ++a) {
      gs[a] = source.field(source_anchor[a], xv) * source_diameter;
      se[a] = geometry.exact(source_anchor[a], xv, gs[a]);
      nearest = std::min(nearest, gs[a]);
    }
    if (nearest > reach || nearest <= 0) continue;  // outside the region, or an anchor itself
    float best = kUnreached, best_terms[3] = {0, 0, 0};
    for (const int y : offered) {
      const int yv = target.sample_vertex(y);
      float terms[3], sum = 0;
      for (int a = 0; a < 3; ++a) {
        const float gt = target.field(target_anchor[a], yv) * target_diameter;
        terms[a] = mismatch(gs[a], kappa * gt, se[a],
                            geometry.target_exact(target.sample_vertex(target_anchor[a]), yv, gt));
        sum += terms[a];
      }
      if (sum < best) best = sum, std::copy(terms, terms + 3, best_terms);
    }
    if (best == kUnreached) continue;
    for (int a = 0; a < 3; ++a) residual[a] += best_terms[a];
    ++matched;
  }
  if (matched == 0) return;
  for (int a = 0; a < 3; ++a) triplet.vote[a] = std::exp(-(residual[a] / matched / mean_side) / kVoteSigma);
}

using PointMap = std::vector<Pair>;

// Step 3: maximum-vote maps, each with the previous one's least confident match's two
// extremities removed, down to 3 matches.
std::vector<PointMap> combine(std::vector<std::vector<double>> votes) {
  std::vector<PointMap> maps;
  while (true) {
    PointMap map;
    const std::vector<int> assignment = max_weight_assignment(votes);
    for (int i = 0; i < static_cast<int>(assignment.size()); ++i)
      if (assignment[i] >= 0 && votes[i][assignment[i]] > 0) map.push_back({i, assignment[i]});
    if (map.size() < 3) break;
    maps.push_back(map);
    const Pair weakest = *std::min_element(map.begin(), map.end(), [&](const Pair& a, const Pair& b) {
      return votes[a.source][a.target] < votes[b.source][b.target];
    });
    for (auto& row : votes) row[weakest.target] = 0;
    std::fill(votes[weakest.source].begin(), votes[weakest.source].end(), 0.0);
  }
  return maps;
}

bool contains_all(const PointMap& map, const PointMap& part) {
  return std::all_of(part.begin(), part.end(), [&](const Pair& p) {
    return std::any_of(map.begin(), map.end(), [&](const Pair& q) { return q.source == p.source && q.target == p.target; });
  });
}

ExtremityMap to_extremity_map(const Points& s, const Points& t, const Eigen::MatrixXd& target_distances,
                              const PointMap& map) {
  ExtremityMap result;
  const int m = static_cast<int>(map.size());
  std::vector<std::vector<double>> gs(m, std::vector<double>(m));
  std::vector<std::vector<char>> exact(m, std::vector<char>(m));
  std::vector<int> target_of;
  for (int a = 0; a < m; ++a) {
    result.source_samples.push_back(s.samples[map[a].source]);
    result.target_samples.push_back(t.samples[map[a].target]);
    target_of.push_back(map[a].target);
    for (int b = 0; b < m; ++b)
      gs[a][b] = s.distance[map[a].source][map[b].source], exact[a][b] = s.exact[map[a].source][map[b].source];
  }
  result.distortion = scale_invariant_distortion(gs, target_distances, exact, t.exact, target_of, result.scale);
  return result;
}

// Rank and qualify: the pairs (source point, target point) among the kQualifiedPerPoint
// best-ranked of either point.
std::vector<Pair> qualified_pairs(const Points& s, const Points& t) {
  const int ns = static_cast<int>(s.samples.size()), nt = static_cast<int>(t.samples.size());
  std::vector<std::vector<double>> ranked(ns, std::vector<double>(nt));
  for (int i = 0; i < ns; ++i)
    for (int j = 0; j < nt; ++j) ranked[i][j] = ranked_distortion(s, t, i, j);
  std::vector<std::vector<char>> qualified(ns, std::vector<char>(nt, 0));
  std::vector<int> order;
  for (int i = 0; i < ns; ++i) {
    order.resize(nt);
    for (int j = 0; j < nt; ++j) order[j] = j;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return ranked[i][a] < ranked[i][b]; });
    for (int q = 0; q < std::min(nt, kQualifiedPerPoint); ++q) qualified[i][order[q]] = 1;
  }
  for (int j = 0; j < nt; ++j) {
    order.resize(ns);
    for (int i = 0; i < ns; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return ranked[a][j] < ranked[b][j]; });
    for (int q = 0; q < std::min(ns, kQualifiedPerPoint); ++q) qualified[order[q]][j] = 1;
  }
  std::vector<Pair> pairs;
  for (int i = 0; i < ns; ++i)
    for (int j = 0; j < nt; ++j)
      if (qualified[i][j]) pairs.push_back({i, j});
  return pairs;
}

// Vote: every triplet of qualified pairs with distinct points on both sides and a
// consistent scale votes for its pairs; `votes` gets each pair's total.
std::vector<Triplet> voted_triplets(const PartGeometry& geometry, const Points& s, const Points& t,
                                    const std::vector<Pair>& pairs, int threads,
                                    std::vector<std::vector<double>>& votes, const JobControl& control) {
  std::vector<Triplet> triplets;
  const int np = static_cast<int>(pairs.size());
  for (int a = 0; a < np; ++a)
    for (int b = a + 1; b < np; ++b)
      for (int c = b + 1; c < np; ++c) {
        const Pair &p = pairs[a], &q = pairs[b], &r = pairs[c];
        if (p.source == q.source || p.source == r.source || q.source == r.source || p.target == q.target ||
            p.target == r.target || q.target == r.target)
          continue;
        Triplet triplet;
        triplet.pairs[0] = p, triplet.pairs[1] = q, triplet.pairs[2] = r;
        if (triplet_scale(s, t, triplet)) triplets.push_back(triplet);
      }
  if (triplets.empty()) throw InputError("ravac: no triplet of qualified extremity matches is consistent");
  parallel_for(static_cast<int>(triplets.size()), threads, [&](int k, int) {
    if (k % 64 == 0) control.check_cancelled();
    vote_triplet(geometry, s, t, triplets[k]);
  });
  votes.assign(s.samples.size(), std::vector<double>(t.samples.size(), 0));
  for (const Triplet& triplet : triplets)  // in order: the sums do not depend on the threads
    for (int a = 0; a < 3; ++a) votes[triplet.pairs[a].source][triplet.pairs[a].target] += triplet.vote[a];
  return triplets;
}

// Combine, then the best-supported triplets (their pairs' total votes) not already within a
// map, up to `wanted` maps; `combined` gets the number of combined maps.
std::vector<PointMap> combined_maps(const std::vector<std::vector<double>>& votes, const std::vector<Triplet>& triplets,
                                    int wanted, size_t& combined) {
  std::vector<PointMap> maps = combine(votes);
  combined = maps.size();
  auto support = [&](const Triplet& x) {
    double sum = 0;
    for (const Pair& p : x.pairs) sum += votes[p.source][p.target];
    return sum;
  };
  std::vector<int> by_support(triplets.size());
  for (size_t k = 0; k < triplets.size(); ++k) by_support[k] = static_cast<int>(k);
  std::stable_sort(by_support.begin(), by_support.end(),
                   [&](int a, int b) { return support(triplets[a]) > support(triplets[b]); });
  for (const int k : by_support) {
    if (static_cast<int>(maps.size()) >= wanted) break;
    const PointMap triplet(std::begin(triplets[k].pairs), std::end(triplets[k].pairs));
    if (std::none_of(maps.begin(), maps.end(), [&](const PointMap& m) { return contains_all(m, triplet); }))
      maps.push_back(triplet);
  }
  if (static_cast<int>(maps.size()) > wanted) maps.resize(wanted);
  return maps;
}

}  // namespace

std::vector<ExtremityMap> ravac_extremity_maps(const PartGeometry& geometry, int wanted, int threads,
                                               std::vector<std::string>& notes, const JobControl& control) {
  const PreprocessedShape& source = geometry.shape;
  const PreprocessedShape& target = geometry.target;
  bool source_short = false, target_short = false;
  std::vector<int> source_samples =
      search_samples(source, geometry.boundary_distance, static_cast<float>(kRimBand * source.diameter()), kPoints,
                     source_short);
  std::vector<int> target_samples =
      search_samples(target, geometry.target_boundary_distance, static_cast<float>(kRimBand * target.diameter()),
                     kPoints, target_short);
  // Points that are not extremities have no extremity counterpart: the other shape then
  // offers its spread samples.
  if (source_short) target_samples = spread_samples(target, geometry.target_boundary_distance, kFinerPoints);
  if (target_short) source_samples = spread_samples(source, geometry.boundary_distance, kFinerPoints);
  const Points s = points_of(source, geometry.boundary_distance, source_samples);
  const Points t = points_of(target, geometry.target_boundary_distance, target_samples);
  const int ns = static_cast<int>(s.samples.size()), nt = static_cast<int>(t.samples.size());
  if (ns < 3 || nt < 3) throw InputError("ravac: each shape needs 3 samples away from its boundary");

  const std::vector<Pair> pairs = qualified_pairs(s, t);
  std::vector<std::vector<double>> votes;
  const std::vector<Triplet> triplets = voted_triplets(geometry, s, t, pairs, threads, votes, control);
  size_t combined = 0;
  const std::vector<PointMap> maps = combined_maps(votes, triplets, wanted, combined);

  const Eigen::MatrixXd target_distances = [&] {
    Eigen::MatrixXd d(nt, nt);
    for (int i = 0; i < nt; ++i)
      for (int j = 0; j < nt; ++j) d(i, j) = t.distance[i][j];
    return d;
  }();
  std::vector<ExtremityMap> result;
  for (const PointMap& map : maps) result.push_back(to_extremity_map(s, t, target_distances, map));
  notes.push_back("ravac: " + std::to_string(ns) + " x " + std::to_string(nt) + " points, " +
                  std::to_string(pairs.size()) + " qualified matches, " + std::to_string(triplets.size()) +
                  " consistent triplets voted; " + std::to_string(combined) + " combined maps (largest " +
                  std::to_string(maps.empty() || combined == 0 ? 0 : maps.front().size()) + " matches) and " +
                  std::to_string(maps.size() - combined) + " triplets grown");
  return result;
}

}  // namespace isocorr
