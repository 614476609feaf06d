#include "part_extremity_search.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <string>

#include "isocorr/matching/matcher.h"
#include "isocorr/util/error.h"
#include "isocorr/util/parallel.h"
#include "part_growth.h"

namespace isocorr {
namespace {

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

}  // namespace

std::vector<ExtremityMap> part_search_candidates(const PartGeometry& part, const MatchSettings& settings, int threads,
                                                 Level0Diagnostics& level0, std::vector<int>& ranks,
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
  for (const auto& map : all_maps) level0.maps.push_back({map.target_samples, map.distortion});

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

}  // namespace isocorr
