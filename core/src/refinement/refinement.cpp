#include "isocorr/refinement/refinement.h"

#include <algorithm>
#include <optional>
#include <unordered_map>
#include <utility>

#include "isocorr/diagnosis/verdict.h"
#include "isocorr/matching/orientation.h"
#include "isocorr/refinement/candidate_screening.h"
#include "isocorr/util/error.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// Two tracked maps that send at least this share of their common source samples to the
// same target sample end in the same place: refining both would measure one map twice.
constexpr double kSameMapShare = 0.8;

constexpr size_t kFinishedCandidates = 3;
// The two best raw candidates are always finished; a third only when its raw curvature
// disagreement is at most this much (relative) above the best raw candidate's. Raw
// curvature ranks the candidates only roughly: a swapped limb may be 10% below the right
// map raw and only finishing shows it (SCAPE 000 -> 011); a turned body was more than 13%
// below the right map raw, so the right map (raw 0.0825) was never finished and the
// turned one (finished 0.077) won (faust_reg6890 005 -> 006, AVX2 build). The margin
// keeps a third finishing (1.8 s at 52K) for near ties: michael's 0.63 partial mirror is
// 20% above the best raw.
constexpr size_t kAlwaysFinished = 2;
constexpr double kFinishedCurvatureMargin = 0.15;

bool same_map(const TrackedMap& a, const TrackedMap& b) {
  std::unordered_map<int, int> image_of;
  for (const SamplePair& p : a.pairs) image_of[p.source_sample] = p.target_sample;
  int common = 0, same = 0;
  for (const SamplePair& p : b.pairs) {
    const auto it = image_of.find(p.source_sample);
    if (it == image_of.end()) continue;
    ++common;
    same += it->second == p.target_sample;
  }
  return common > 0 && same >= kSameMapShare * common;
}

// Two refined maps that send 80% of the source's spectral samples to the same target
// vertex or one of its neighbours are one map: ZoomOut from two distinct tracked starts
// often ends in the same place.
bool same_dense_map(const std::vector<int>& a, const std::vector<int>& b, const std::vector<int>& samples,
                    const MeshTopology& target_topology) {
  std::vector<int> at_a, at_b;
  for (const int v : samples) at_a.push_back(a[v]), at_b.push_back(b[v]);
  return same_images(at_a, at_b, target_topology);
}

void require_spectral_bases(const PreprocessedShape& source, const PreprocessedShape& target) {
  if (source.spectral_basis().cols() == 0 || target.spectral_basis().cols() == 0)
    throw InputError("refinement needs the shapes' spectral basis: spectral_basis must be positive");
}

// What finishing one map did.
struct Finishing {
  OutlierRepair repair;
  MirrorRepair mirror_repair;
};

// The last stages of every refined map, on `threads` workers. The repair goes first: the
// rigidity polish would spread a misplaced region into its surroundings.
Finishing finish_map(const PreprocessedShape& source, const PreprocessedShape& target, const RigidityPolish& rigidity,
                     const MatchSettings& settings, SpectralMap& map, const JobControl& control, int threads) {
  Finishing finishing;
  if (settings.outlier_repair) finishing.repair = repair_outliers(source, target, map.image, threads, control);
  rigidity.polish(map, control, threads);
  return finishing;
}

// finish_map with the polish's mirror repair (when settings.rigidity.mirror_repair), which
// unfolds mirrored segments.
Finishing finish_map_with_mirror_repair(const PreprocessedShape& source, const PreprocessedShape& target,
                                        const RigidityPolish& rigidity, const MatchSettings& settings,
                                        SpectralMap& map, const JobControl& control, int threads) {
  if (!settings.rigidity.mirror_repair) return finish_map(source, target, rigidity, settings, map, control, threads);
  Finishing finishing;
  if (settings.outlier_repair) finishing.repair = repair_outliers(source, target, map.image, threads, control);
  finishing.mirror_repair = rigidity.polish_with_mirror_repair(map, control, threads);
  return finishing;
}

// The optional spectral polish of a finished map (zoomout_polish_k_end and the curvature
// term): it starts from the map's functional map and leaves a spectral map, so `finish`
// runs again when it ran.
template <class Finish>
void spectral_polish(const SpectralSide& source_side, const SpectralSide& target_side, const ZoomOutOptions& options,
                     SpectralMap& map, const JobControl& control, const Finish& finish) {
  if (zoomout_polish(source_side, target_side, options, map, control)) finish();
}

// refine_from_pairs with the pair's rigidity system already built (its three sparse
// factors are the same for every refinement of the pair).
SpectralMap refine_from_pairs_with(const PreprocessedShape& source, const PreprocessedShape& target,
                                   const RigidityPolish& rigidity, const std::vector<std::pair<int, int>>& pairs,
                                   const MatchSettings& settings, const JobControl& control) {
  const ZoomOutOptions& options = settings.zoomout;
  const SpectralSide source_side = spectral_side(source), target_side = spectral_side(target);
  SpectralMap map = zoomout(source_side, target_side, pairs, options, control);
  auto finish = [&] {
    finish_map_with_mirror_repair(source, target, rigidity, settings, map, control, control.threads);
  };
  finish();
  spectral_polish(source_side, target_side, options, map, control, finish);
  return map;
}

// refine_again with the pair's rigidity system already built.
SpectralMap refine_again_with(const PreprocessedShape& source, const PreprocessedShape& target,
                              const RigidityPolish& rigidity, const SpectralMap& map, const MatchSettings& settings,
                              const JobControl& control) {
  std::vector<std::pair<int, int>> pairs;
  for (const int v : source.spectral_samples()) pairs.emplace_back(v, map.image[v]);
  // The map is right everywhere already: it needs no low-frequency stage to find its way,
  // and one would pull it away from the truth again. Half the basis leaves it room to move
  // (SCAPE's first 10 pairs: 0.0082 starting at 50 of 100 functions, 0.0083 at 100).
  MatchSettings again = settings;
  again.zoomout.k_start = std::max(1, settings.zoomout.k_end / 2);
  return refine_from_pairs_with(source, target, rigidity, pairs, again, control);
}

}  // namespace

SpectralMap refine_from_pairs(const PreprocessedShape& source, const PreprocessedShape& target,
                              const std::vector<std::pair<int, int>>& pairs, const MatchSettings& settings,
                              const JobControl& control) {
  require_spectral_bases(source, target);
  const RigidityPolish rigidity(source, target, settings.rigidity);
  return refine_from_pairs_with(source, target, rigidity, pairs, settings, control);
}

SpectralMap refine_again(const PreprocessedShape& source, const PreprocessedShape& target, const SpectralMap& map,
                         const MatchSettings& settings, const JobControl& control) {
  require_spectral_bases(source, target);
  const RigidityPolish rigidity(source, target, settings.rigidity);
  return refine_again_with(source, target, rigidity, map, settings, control);
}

namespace {

// The best ranked tracked maps whose sample images differ, at most `count` of them.
std::vector<int> pick_distinct(const std::vector<TrackedMap>& tracked, const std::vector<int>& ranked, int count) {
  std::vector<int> picked;
  for (const int index : ranked) {
    if (static_cast<int>(picked.size()) >= count) break;
    bool distinct = true;
    for (const int other : picked) distinct = distinct && !same_map(tracked[other], tracked[index]);
    if (distinct) picked.push_back(index);
  }
  return picked;
}

// One refinement of a pair's tracked maps, stage by stage (refine_and_choose lists them in
// order); each stage leaves its result in the members the next one reads, and its time in
// the result under its name.
class CandidateRefinement {
 public:
  CandidateRefinement(const PreprocessedShape& source, const PreprocessedShape& target, const MatchSettings& settings,
                      const JobControl& control, const LandmarkGeometry& landmarks)
      : source_(source), target_(target), settings_(settings), control_(control), landmarks_(landmarks),
        options_(settings.zoomout), source_side_(spectral_side(source)),
        target_side_(spectral_side(target)), threads_(resolve_thread_count(control.threads)),
        clock_(result_.timings) {}

  // The picked tracked maps are screened by a short refinement on the samples;
  // refine_candidates of them, from the ranking and the screen in turn, go on
  // (candidate_screening.h).
  void screen(const std::vector<TrackedMap>& tracked, const std::vector<int>& picked) {
    std::vector<ScreenedStart> starts =
        screen_tracked_maps(source_, target_, tracked, picked, std::min(settings_.screen_k_end, options_.k_end),
                            options_, control_, landmarks_.pairs());
    for (const ScreenedStart& start : starts) result_.screened.push_back(start.evidence);
    starts_ = starts_to_refine(std::move(starts), settings_.refine_candidates, settings_.orientation_margin,
                               target_.geodesics().topology());
    clock_.finish("screen");
  }

  // Each start refined on the samples to the full basis, then on every vertex. The starts
  // are refined side by side, the workers shared out among them: they are independent, and
  // each one's own loops left a core idle for much of their time (a 52K pair's four
  // refinements 2.6 s). Every result is the same whatever the number of workers.
  void refine() {
    // The pair's rigidity system (three sparse factors), built once the screen is done.
    rigidity_.emplace(source_, target_, settings_.rigidity);
    refined_starts_.resize(starts_.size());
    parallel_for_sharing(static_cast<int>(starts_.size()), threads_, [&](int i, int workers) {
      const JobControl shared = control_.with_threads(workers);
      continue_on_samples(source_side_, target_side_, options_.k_end, options_, starts_[i].sampled, shared);
      refined_starts_[i] = zoomout_dense(source_side_, target_side_, starts_[i].sampled, options_, shared);
    });
    control_.check_cancelled();
    clock_.finish("refine");
  }

  // A map refined twice would be finished and measured twice, for nothing.
  void drop_duplicates() {
    for (size_t i = 0; i < starts_.size(); ++i) {
      SpectralMap& map = refined_starts_[i];
      const bool seen = std::any_of(maps_.begin(), maps_.end(), [&](const SpectralMap& other) {
        return same_dense_map(other.image, map.image, source_.spectral_samples(), target_.geodesics().topology());
      });
      if (seen) continue;
      maps_.push_back(std::move(map));
      tracked_of_.push_back(starts_[i].evidence.tracked_index);
    }
    clock_.finish("drop_duplicates");
  }

  // Which maps are finished. A mirror image stays one when finished (it reverses handedness
  // everywhere): the handedness of the spectral maps decides which are worth finishing.
  // Finishing costs as much as the spectral refinement; only the kFinishedCandidates maps
  // that pass the mirror test and whose raw curvature agrees best are finished, and only
  // finished maps compete while one is eligible. A raw map is no match for a finished one:
  // the polish tears a swapped limb's seams open, so a partial flip's curvature rises when
  // finished (SCAPE 000 -> 011: raw 0.124 against the right map's 0.136, finished 0.144
  // against 0.128).
  void preselect() {
    std::vector<double> handedness(maps_.size());
    for (size_t i = 0; i < maps_.size(); ++i)
      handedness[i] = dense_orientation_agreement(source_.mesh(), source_.normals(), target_.mesh(),
                                                  target_.normals(), maps_[i].image);
    const double best_handedness = maps_.empty() ? 0 : *std::max_element(handedness.begin(), handedness.end());
    std::vector<std::pair<double, size_t>> by_curvature;
    const double mirror_below = mirror_threshold(best_handedness, settings_.orientation_margin);
    // Maps off the landmarks would lose the choice to any on them: not worth finishing.
    std::vector<bool> on_landmarks(maps_.size());
    for (size_t i = 0; i < maps_.size(); ++i)
      on_landmarks[i] = landmarks_.largest_error(maps_[i].image) <= kLandmarkTolerance;
    const bool some_on = std::find(on_landmarks.begin(), on_landmarks.end(), true) != on_landmarks.end();
    for (size_t i = 0; i < maps_.size(); ++i)
      if (handedness[i] >= mirror_below && (on_landmarks[i] || !some_on))
        by_curvature.emplace_back(curvature_disagreement(source_, target_, maps_[i].image), i);
    std::sort(by_curvature.begin(), by_curvature.end());
    while (by_curvature.size() > kAlwaysFinished &&
           by_curvature.back().first > (1 + kFinishedCurvatureMargin) * by_curvature[0].first)
      by_curvature.pop_back();
    if (by_curvature.size() > kFinishedCandidates) by_curvature.resize(kFinishedCandidates);
    finished_.assign(maps_.size(), false);
    for (const auto& [curvature, i] : by_curvature) finished_[i] = true;
    clock_.finish("preselect");
  }

  // The preselected maps finished (outlier repair, rigidity polish without the mirror
  // repair) and every map measured by dense evidence. Candidates are finished before the
  // choice, not only the winner: a right map that converged less well (SCAPE 001 -> 004,
  // 006: D_grd 0.016-0.02 against 0.010 typical) lost to a turned body on heat signatures;
  // finished, it wins (signature 0.0145 against 0.0150 on 001 -> 004). Repaired candidates
  // lost SCAPE 001 -> 007 and 001 -> 012 to mirrored maps and won 007 -> 009 (every SCAPE
  // pair: 103 -> 102 flip-free), so the mirror repair is the winner's alone.
  void finish() {
    finishings_.resize(maps_.size());
    result_.candidates.resize(maps_.size());
    // The finishings are the costly bodies: one costs several measurings.
    parallel_for_costly_first(finished_, threads_, [&](int i, int workers) {
      if (finished_[i]) finishings_[i] = finish_one(maps_[i], workers);
      result_.candidates[i].tracked_index = tracked_of_[i];
      result_.candidates[i].finished = finished_[i];
      measure(i, workers);
    });
    control_.check_cancelled();
    clock_.finish("finish");
  }

  // The choice by dense evidence (dense_choice.h). A winner that was not finished (no
  // finished candidate was eligible) is finished and measured now.
  void choose() {
    result_.chosen = choose_dense_candidate(result_.candidates, settings_.orientation_margin, result_.why);
    decide_near_tie();
    const int chosen = result_.chosen;
    if (!finished_[chosen]) {
      finishings_[chosen] = finish_one(maps_[chosen], control_.threads);
      measure(chosen, control_.threads);
    }
    last_ = finishings_[chosen];
    clock_.finish("choose");
  }

  // A near tie between different maps (close_competitors, diagnosis/verdict.h) is decided
  // by both directions' evidence: each tied map's reverse map is measured as a map from the
  // target (its curvature at the target's samples, its distortion between them), and the
  // product of the two scores wins. On the development pairs' five ties this turned SCAPE
  // 007 -> 009 from a whole-body mirror (0.33) to the right map (0.026) and kept the three
  // right winners; 013 -> 014 stayed wrong, all its candidates were. Only tied pairs pay.
  void decide_near_tie() {
    const std::vector<int> close = close_competitors(source_, target_, result_.candidates, result_.chosen);
    if (close.empty()) return;
    std::vector<int> tied = {result_.chosen};
    tied.insert(tied.end(), close.begin(), close.end());
    const int before = result_.chosen;
    double best = 0;
    for (const int i : tied) {
      DenseCandidate& candidate = result_.candidates[i];
      candidate.reverse_score = choice_score(measure_dense_map(target_, source_, maps_[i].reverse_image, maps_[i].image,
                                                               settings_.dense_choice_sources, threads_));
      const double both = candidate.score * candidate.reverse_score;
      if (i == before || both < best) result_.chosen = i, best = both;
    }
    result_.why += "; a near tie with " + std::to_string(close.size()) + " different map" +
                   (close.size() > 1 ? "s" : "") + " was decided by the product of both directions' scores: " +
                   (result_.chosen == before ? "the winner kept" : "candidate " + std::to_string(result_.chosen) + " won");
  }

  // The winner's mirrored segments held at both ends are unfolded before its spectral
  // polish, so that the polish refits around them (every SCAPE pair: D_grd 0.0103 -> 0.0101
  // with the last finishing alone, 0.0093 unfolded first; polishing the unfolded winner
  // before its spectral polish as well gave 0.0096, and cost michael0 -> michael1 5 s).
  void unfold_mirrors() {
    if (settings_.rigidity.mirror_repair) result_.mirror_repair_chosen = rigidity_->unfold_mirrors(winner());
    clock_.finish("unfold_mirrors");
  }

  // The winner's basis grown on the samples up to zoomout_polish_k_end (polish_on_samples,
  // zoomout.h), the curvature term picking the images as it grows. Without a curvature term
  // the winner's dense map is recovered here; with one, the curvature polish recovers it.
  // The candidates' evidence describes their maps before it: it decided the choice.
  void spectral_polish() {
    polish_samples_ = polish_on_samples(source_side_, target_side_, options_, winner(), control_);
    if (polish_samples_ && !has_curvature_polish(source_side_, target_side_, options_)) {
      winner() = zoomout_dense(source_side_, target_side_, *polish_samples_, options_, control_);
      polished_ = true;
      polish_samples_.reset();
    }
    clock_.finish("spectral_polish");
  }

  // The spectral polish's last refits, on the samples and then on every vertex, with the
  // curvature term (curvature_polish, zoomout.h).
  void curvature_polish() {
    if (polish_samples_) {
      winner() =
          isocorr::curvature_polish(source_side_, target_side_, options_, std::move(*polish_samples_), control_);
      polished_ = true;
      polish_samples_.reset();
    }
    clock_.finish("curvature_polish");
  }

  // A winner the spectral polish or the unfolding changed is finished again, now with the
  // mirror repair.
  void finish_with_mirror_repair() {
    if (polished_ || result_.mirror_repair_chosen.segments > 0)
      last_ = finish_one_with_mirror_repair(winner(), control_.threads);
    result_.repair = last_.repair;
    result_.mirror_repair = last_.mirror_repair;
    clock_.finish("finish_with_mirror_repair");
  }

  // settings.refine_passes refinements of the winner from its own images (refine_again).
  void refine_again() {
    for (int pass = 0; pass < settings_.refine_passes; ++pass)
      winner() = refine_again_with(source_, target_, *rigidity_, winner(), settings_, control_);
    clock_.finish("refine_again");
  }

  // settings.rigidity_final_iterations more rigidity iterations (final_polish.h).
  void final_polish() {
    result_.final_polish = extend_rigidity_polish(source_, target_, settings_.rigidity_final_iterations,
                                                  control_.threads, winner(), control_);
    clock_.finish("final_polish");
  }

  // The winner, as the dense map of the match.
  RefinedMatch result() {
    SpectralMap& map = winner();
    result_.candidates[result_.chosen].forward = map.image;
    result_.dense.forward = std::move(map.image);
    result_.dense.forward_diso = std::move(map.residual);
    result_.dense.reverse = std::move(map.reverse_image);
    result_.dense.reverse_diso = std::move(map.reverse_residual);
    result_.functional_map = std::move(map.c);
    return std::move(result_);
  }

 private:
  SpectralMap& winner() { return maps_[result_.chosen]; }
  Finishing finish_one(SpectralMap& map, int threads) const {
    return finish_map(source_, target_, *rigidity_, settings_, map, control_, threads);
  }
  Finishing finish_one_with_mirror_repair(SpectralMap& map, int threads) const {
    return finish_map_with_mirror_repair(source_, target_, *rigidity_, settings_, map, control_, threads);
  }
  void measure(int i, int threads) {
    DenseCandidate& candidate = result_.candidates[i];
    candidate.forward = maps_[i].image;
    candidate.evidence = measure_dense_map(source_, target_, maps_[i].image, maps_[i].reverse_image,
                                           settings_.dense_choice_sources, threads);
    candidate.landmark_error = landmarks_.largest_error(maps_[i].image);
  }

  const PreprocessedShape& source_;
  const PreprocessedShape& target_;
  const MatchSettings& settings_;
  const JobControl& control_;
  const LandmarkGeometry& landmarks_;
  const ZoomOutOptions options_;
  const SpectralSide source_side_, target_side_;
  std::optional<RigidityPolish> rigidity_;
  const int threads_;
  RefinedMatch result_;
  StageClock clock_;
  std::vector<ScreenedStart> starts_;
  std::vector<SpectralMap> refined_starts_;
  std::vector<SpectralMap> maps_;    // the distinct refined maps
  std::vector<int> tracked_of_;      // the tracked map of each of maps_
  std::vector<bool> finished_;       // per map: finished before the choice
  std::vector<Finishing> finishings_;
  Finishing last_;                   // the winner's latest finishing
  std::optional<SampleMap> polish_samples_;  // the winner between its spectral and curvature polish
  bool polished_ = false;            // the spectral or the curvature polish changed the winner
};

}  // namespace

RefinedMatch refine_and_choose(const PreprocessedShape& source, const PreprocessedShape& target,
                               const std::vector<TrackedMap>& tracked, const std::vector<int>& ranked,
                               const MatchSettings& settings, const JobControl& control,
                               const LandmarkGeometry& landmarks) {
  require_spectral_bases(source, target);
  CandidateRefinement run(source, target, settings, control, landmarks);
  run.screen(tracked, pick_distinct(tracked, ranked, std::max(settings.screen_candidates, settings.refine_candidates)));
  run.refine();
  run.drop_duplicates();
  run.preselect();
  run.finish();
  run.choose();
  run.unfold_mirrors();
  run.spectral_polish();
  run.curvature_polish();
  run.finish_with_mirror_repair();
  run.refine_again();
  run.final_polish();
  return run.result();
}

}  // namespace isocorr
