#include "isocorr/partial/part_matching.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <string>

#include "isocorr/matching/matcher.h"
#include "isocorr/matching/orientation.h"
#include "isocorr/partial/partial_refinement.h"
#include "isocorr/refinement/rigidity_polish.h"
#include "isocorr/util/parallel.h"
#include "part_dense_map.h"
#include "part_extremity_search.h"
#include "part_geometry.h"
#include "part_growth.h"
#include "ravac.h"

namespace isocorr {
namespace {

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
  RigidityPolish(source, target, options, 1.0 / scale).apply(polished, control.with_threads(threads));
  map.forward = std::move(polished.image);
  map.forward_diso = std::move(polished.residual);
}

// Steps 3 and 4 of the part search and its choice, stage by stage (match_part lists them in
// order); each stage leaves its result in the members the next one reads, and its time in
// the result's stage timings.
class PartSearch {
 public:
  PartSearch(const PreprocessedShape& source, const PreprocessedShape& target, const MatchSettings& settings,
             MatchResult& result, const JobControl& control)
      : source_(source), target_(target), settings_(settings), result_(result), control_(control),
        part_(source, target), threads_(resolve_thread_count(control.threads)),
        finish_(finishes_part_maps(settings)), clock_(result.timings.stages) {}

  // Steps 1 and 2: the extremity maps the search starts from, by RAVAC or the part search.
  void propose() {
    control_.report({"part-extremities", 0, 2, 0.0});
    Level0Diagnostics& level0 = result_.diagnostics.level0;
    if (settings_.method == MatchMethod::kRavac) {
      maps_ = ravac_extremity_maps(part_, settings_.part_candidates, threads_, result_.messages.notes, control_);
      for (size_t i = 0; i < maps_.size(); ++i) {
        ranks_.push_back(static_cast<int>(i));
        level0.maps.push_back({maps_[i].target_samples, maps_[i].distortion});
      }
      clock_.finish("ravac");
    } else {
      maps_ = part_search_candidates(part_, settings_, threads_, level0, ranks_, control_);
      clock_.finish("part-candidates");  // extremity maps and their screening
    }
  }

  // Step 3: each candidate's samples grown coarse to fine.
  void grow() {
    control_.report({"part-tracking", 1, 2, 0.3});
    tracked().resize(maps_.size());
    scales_.resize(maps_.size());
    std::atomic<int> done{0};
    const int last_step = 2 * source_.options().decision_level;
    parallel_for(static_cast<int>(maps_.size()), threads_, [&](int i, int) {
      tracked()[i] = grow_sample_map(part_, maps_[i], ranks_[i], last_step, scales_[i], control_);
      control_.report({"part-tracking", 1, 2, 0.3 + 0.4 * (++done) / maps_.size()});
    });
    clock_.finish("part-tracking");
  }

  // Each candidate extended to the part's vertices: a mirrored map reverses most faces there
  // (sample triangles are too coarse to show it), so dense orientation drops mirrors; the
  // rest compete by curvature. Without finishing, every candidate competes on its dense
  // map. With it, only the finalists do, and the rest need only what picks the finalists:
  // orientation and curvature, on a map made on rough_map_vertices (covered share not
  // measured: NaN). Against all 64 made on every vertex: the same result on every cut of
  // the part benchmark (36 development, 24 held out); partial_holes_derived
  // (isocorr-bench --partial) 23.2-24.0 -> 17.9-18.6 s on the 28K cat, 14.0-15.8 ->
  // 11.0-11.8 s on the 16K centaur.
  void make_candidate_maps() {
    control_.report({"part-dense", 2, 2, 0.7});
    dense_.resize(maps_.size());
    curvature_.resize(maps_.size());
    covered_.assign(maps_.size(), std::numeric_limits<double>::quiet_NaN());
    // Breadth first from each candidate's first pair: one order per distinct first sample
    // (the part search's candidates all share theirs, RAVAC's do not).
    for (const ExtremityMap& map : maps_)
      if (!orders_.count(map.source_samples.front()))
        orders_[map.source_samples.front()] =
            breadth_first_order(source_, source_.sample_vertex(map.source_samples.front()));
    target_vertex_areas_ = vertex_areas(target_.mesh());
    part_curvature_.emplace(part_, scales_, threads_);
    const std::vector<char> wanted = finish_ ? rough_map_vertices(source_) : std::vector<char>();
    parallel_for(static_cast<int>(maps_.size()), threads_, [&](int i, int) {
      dense_[i] = dense_part_map(part_, tracked()[i], sample_anchors(target_, tracked()[i].pairs), scales_[i],
                                 visit_order(i), wanted, control_);
      measure(i, !finish_);
      if (finish_) fill_from_parents(visit_order(i), first_image(i), dense_[i].forward);  // for the report
    });
  }

  // The finalists, made on every vertex and finished, are measured again and compete: a
  // rough map's curvature carries a sample spacing's worth of noise.
  void finish_finalists() {
    finalists_ = part_finalists(tracked(), curvature_, settings_.orientation_threshold,
                                finish_ ? kFinalists : static_cast<int>(maps_.size()));
    refined_maps_.resize(maps_.size());
    if (!finish_) return;
    // Half the winner's iterations: the comparison needs the sample noise taken out, not
    // the slide converged. Against all of them: the same result on 59 of the part
    // benchmark's 60 cuts (the 60th wrong either way), partial_holes_derived's 28K cat 27.6
    // -> 24.5 s (23.8 without finalists).
    RigidityOptions finalist_polish = settings_.rigidity;
    finalist_polish.iterations = std::max(1, settings_.rigidity.iterations / 2);
    parallel_for(static_cast<int>(finalists_.size()), threads_, [&](int k, int) {
      const int i = finalists_[k];
      dense_[i] = dense_part_map(part_, tracked()[i], sample_anchors(target_, tracked()[i].pairs), scales_[i],
                                 visit_order(i), {}, control_);
      if (refine_if_better(i, 1, dense_[i].forward)) refined_maps_[i] = dense_[i].forward;
      polish_part_map(source_, target_, finalist_polish, scales_[i], 1, dense_[i], control_);  // side by side
      measure(i, true);
    });
  }

  // The winner: least curvature disagreement among the finalists that keep handedness. The
  // sample distortion the candidates were grown by cannot judge them (a map grown from
  // wrong extremities trims them away, and one-sided terms near a cut forgive it);
  // curvature is evidence none of them was fitted to. Measured on cuts
  // (isocorr-bench-partial, 16 candidates): right on 12 of 36 cuts, against 7 by
  // orientation then sample distortion. Finishing 6 finalists first (64 candidates): 25 ->
  // 26 of 36 (FAUST 000 -> 004's 54% ball: its right rough map covered 0.75 and lost to a
  // turned body at kMinCoveredShare); on the cuts of faust_reg6890 and faust_remeshed_lps
  // 23 of 24 either way. Maps that fold the part onto much less than its own area go only
  // when no other is upright (min_covered).
  void choose() {
    const double min_covered = finish_ ? kMinCoveredShareFinished : kMinCoveredShare;
    auto least_curvature = [&](double covered_at_least) {
      int best = -1;
      for (int i : finalists_)
        if (tracked()[i].orientation >= settings_.orientation_threshold && covered_[i] >= covered_at_least &&
            (best < 0 || curvature_[i] < curvature_[best]))
          best = i;
      return best;
    };
    int best = least_curvature(min_covered);
    if (best < 0) best = least_curvature(0);
    chosen_ = result_.diagnostics.tracking.chosen = best >= 0 ? best : rank_tracked(tracked(), settings_).front();
    // The candidates' maps are done with: the winner is made again from vertex-accurate anchors.
    for (int i = 0; i < static_cast<int>(maps_.size()); ++i) {
      const bool finalist = finish_ && std::find(finalists_.begin(), finalists_.end(), i) != finalists_.end();
      result_.diagnostics.part.candidates.push_back({tracked()[i].orientation, curvature_[i], covered_[i],
                                                     scales_[i], tracked()[i].diso, maps_[i].distortion, finalist,
                                                     i == chosen_, std::move(dense_[i].forward)});
    }
  }

  // The winner's dense map: its finalist's spectral refinement when one was kept, else made
  // from vertex-accurate anchors; then the complete pipeline's last stage, at the part's
  // scale: the descent leaves each vertex where its anchors' distances agree best, a sample
  // spacing's worth of noise the polish takes out (isocorr-bench-partial: Kim error of
  // right maps 0.052 -> 0.050, and a map compared against the complete pipeline's polished
  // one is compared like for like: faust 002 -> 007's 46% ball now keeps the part search's
  // right map).
  DenseMap make_winner() {
    const double scale = scales_[chosen_];
    DenseMap chosen;
    if (!refined_maps_[chosen_].empty()) {
      // Its refined map is already finer than one made from vertex-accurate anchors.
      chosen.forward = std::move(refined_maps_[chosen_]);
      result_.messages.notes.push_back("part search: the chosen map is its finalist's spectral refinement");
    } else {
      const TrackedMap& winner = tracked()[chosen_];
      const TargetAnchors anchors = vertex_accurate_anchors(part_, winner.pairs, scale, threads_, control_);
      chosen = dense_part_map(part_, winner, anchors, scale, visit_order(chosen_), {}, control_);
      if (finish_) {
        const bool refined = refine_if_better(chosen_, threads_, chosen.forward);
        result_.messages.notes.push_back(
            std::string("part search: the chosen map made from vertex-accurate anchors, its spectral refinement ") +
            (refined ? "kept" : "dropped (its curvature agreed less, or it lost handedness)"));
      }
    }
    if (finish_) polish_part_map(source_, target_, settings_.rigidity, scale, threads_, chosen, control_);
    add_part_reverse_map(source_, target_, scale, chosen);
    clock_.finish("part-dense");
    result_.quality.part_scale = scale;
    return chosen;
  }

 private:
  std::vector<TrackedMap>& tracked() { return result_.diagnostics.tracking.maps; }
  const VisitOrder& visit_order(int i) const { return orders_.at(maps_[i].source_samples.front()); }
  int first_image(int i) { return target_.sample_vertex(tracked()[i].pairs.front().target_sample); }

  // The evidence the choice weighs, of candidate i's dense map (the covered share needs a
  // map on every vertex).
  void measure(int i, bool with_covered_share) {
    tracked()[i].orientation = dense_orientation_agreement(source_.mesh(), source_.normals(), target_.mesh(),
                                                           target_.normals(), dense_[i].forward);
    curvature_[i] = part_curvature_->disagreement(dense_[i].forward, scales_[i]);
    if (with_covered_share) covered_[i] = covered_share(source_, target_, target_vertex_areas_, scales_[i], dense_[i]);
  }

  // Each finalist's map refined spectrally (partial_refinement.h) before its polish, kept
  // only if it then agrees better in curvature and keeps handedness: a refinement that
  // folds a limb over (SCAPE 000 -> 002's 47% ball: a right map's orientation 0.79 -> 0.35)
  // is dropped, as the rigidity polish could not undo it. Both are compared unpolished.
  bool refine_if_better(int i, int workers, std::vector<int>& forward) {
    std::vector<int> refined = refine_part_map_spectrally(source_, target_, scales_[i], settings_.zoomout, forward,
                                                          control_.with_threads(workers));
    const double orientation =
        dense_orientation_agreement(source_.mesh(), source_.normals(), target_.mesh(), target_.normals(), refined);
    const bool kept = orientation >= settings_.orientation_threshold &&
                      part_curvature_->disagreement(refined, scales_[i]) <
                          part_curvature_->disagreement(forward, scales_[i]);
    if (kept) forward = std::move(refined);
    return kept;
  }

  const PreprocessedShape& source_;
  const PreprocessedShape& target_;
  const MatchSettings& settings_;
  MatchResult& result_;
  const JobControl& control_;
  const PartGeometry part_;
  const int threads_;
  const bool finish_;  // finishes_part_maps
  StageClock clock_;
  std::vector<ExtremityMap> maps_;  // the candidates' extremity maps
  std::vector<int> ranks_;          // each one's rank among all extremity maps
  std::vector<double> scales_;      // each one's kappa, from its grown map
  std::map<int, VisitOrder> orders_;  // by first source sample
  std::vector<double> target_vertex_areas_;
  std::optional<PartCurvature> part_curvature_;
  std::vector<DenseMap> dense_;
  std::vector<double> curvature_, covered_;
  std::vector<int> finalists_;
  std::vector<std::vector<int>> refined_maps_;  // a finalist's kept refinement, unpolished
  int chosen_ = 0;
};

}  // namespace

DenseMap match_part(const PreprocessedShape& source, const PreprocessedShape& target, const MatchSettings& settings,
                    MatchResult& result, const JobControl& control) {
  PartSearch search(source, target, settings, result, control);
  search.propose();
  search.grow();
  search.make_candidate_maps();
  search.finish_finalists();
  search.choose();
  return search.make_winner();
}

DenseMap refine_as_part_map(const PreprocessedShape& source, const PreprocessedShape& target,
                            const MatchSettings& settings, double scale, const std::vector<int>& forward,
                            const JobControl& control) {
  const int threads = resolve_thread_count(control.threads);
  DenseMap map;
  map.forward = refine_part_map_spectrally(source, target, scale, settings.zoomout, forward, control);
  polish_part_map(source, target, settings.rigidity, scale, threads, map, control);
  return map;
}

}  // namespace isocorr
