#include "isocorr/refinement/refinement.h"

#include <algorithm>
#include <unordered_map>
#include <utility>

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

RigidityOptions rigidity_options(const MatchSettings& settings) {
  RigidityOptions options = settings.rigidity;
  options.threads = settings.threads;
  return options;
}

// What finishing one map did.
struct Finishing {
  OutlierRepair repair;
  MirrorRepair mirror_repair;
};

// The last stages of every refined map, on `threads` workers. The repair goes first: the
// rigidity polish would spread a misplaced region into its surroundings. `mirror_repair`
// (with settings.rigidity.mirror_repair) lets the polish unfold mirrored segments.
Finishing finish_map(const PreprocessedShape& source, const PreprocessedShape& target, const RigidityPolish& rigidity,
                     const MatchSettings& settings, SpectralMap& map, const JobControl& control, int threads,
                     bool mirror_repair) {
  Finishing finishing;
  if (settings.outlier_repair) finishing.repair = repair_outliers(source, target, map.image, threads, control);
  finishing.mirror_repair = rigidity.apply(map, control, threads, mirror_repair && settings.rigidity.mirror_repair);
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
  ZoomOutOptions options = settings.zoomout;
  options.threads = settings.threads;
  const SpectralSide source_side = spectral_side(source), target_side = spectral_side(target);
  SpectralMap map = zoomout(source_side, target_side, pairs, options, control);
  auto finish = [&] { finish_map(source, target, rigidity, settings, map, control, settings.threads, true); };
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
  const RigidityPolish rigidity(source, target, rigidity_options(settings));
  return refine_from_pairs_with(source, target, rigidity, pairs, settings, control);
}

SpectralMap refine_again(const PreprocessedShape& source, const PreprocessedShape& target, const SpectralMap& map,
                         const MatchSettings& settings, const JobControl& control) {
  require_spectral_bases(source, target);
  const RigidityPolish rigidity(source, target, rigidity_options(settings));
  return refine_again_with(source, target, rigidity, map, settings, control);
}

RefinedMatch refine_and_choose(const PreprocessedShape& source, const PreprocessedShape& target,
                               const std::vector<TrackedMap>& tracked, const std::vector<int>& ranked,
                               const MatchSettings& settings, const JobControl& control) {
  require_spectral_bases(source, target);
  RefinedMatch result;
  StageClock clock(result.timings);
  // The best ranked distinct tracked maps are screened by a short refinement on the
  // samples; refine_candidates of them, from the ranking and the screen in turn, go on
  // (candidate_screening.h).
  const int screened_count = std::max(settings.screen_candidates, settings.refine_candidates);
  std::vector<int> picked;
  for (const int index : ranked) {
    if (static_cast<int>(picked.size()) >= screened_count) break;
    bool distinct = true;
    for (const int other : picked) distinct = distinct && !same_map(tracked[other], tracked[index]);
    if (distinct) picked.push_back(index);
  }
  ZoomOutOptions options = settings.zoomout;
  options.threads = settings.threads;
  std::vector<ScreenedStart> starts = screen_tracked_maps(
      source, target, tracked, picked, std::min(settings.screen_k_end, options.k_end), options, control);
  for (const ScreenedStart& start : starts) result.screened.push_back(start.evidence);
  starts = starts_to_refine(std::move(starts), settings.refine_candidates, settings.orientation_margin,
                            target.geodesics().topology());
  clock.finish("screen");

  const SpectralSide source_side = spectral_side(source), target_side = spectral_side(target);
  const RigidityPolish rigidity(source, target, rigidity_options(settings));
  // Candidates are finished before the choice, not only the winner: a right map that
  // converged less well (SCAPE 001 -> 004, 006: D_grd 0.016-0.02 against 0.010 typical)
  // lost to a turned body on heat signatures; finished, it wins (signature 0.0145 against
  // 0.0150 on 001 -> 004).
  // The candidates are finished without the mirror repair, the winner with it: repaired
  // candidates lost SCAPE 001 -> 007 and 001 -> 012 to mirrored maps and won 007 -> 009
  // (every SCAPE pair: 103 -> 102 flip-free). The winner's mirrored segments are unfolded
  // before its spectral polish too, so that the polish refits around them (every SCAPE
  // pair: D_grd 0.0103 -> 0.0101 with the last finishing alone, 0.0093 unfolded first;
  // polishing the unfolded winner before its spectral polish as well gave 0.0096, and
  // cost michael0 -> michael1 5 s).
  auto finish = [&](SpectralMap& map, Finishing& finishing, int threads, bool mirror_repair) {
    finishing = finish_map(source, target, rigidity, settings, map, control, threads, mirror_repair);
  };
  // The candidates are refined, finished and measured side by side, the workers shared
  // out among them: they are independent, and each one's own loops left a core idle for
  // much of their time (a 52K pair's four refinements 2.6 s, its finishings 2.4 s each).
  // Every result is the same whatever the number of workers.
  const int threads = resolve_thread_count(settings.threads);
  std::vector<SpectralMap> refined_starts(starts.size());
  parallel_for_sharing(static_cast<int>(starts.size()), threads, [&](int i, int workers) {
    ZoomOutOptions shared_out = options;
    shared_out.threads = workers;
    continue_on_samples(source_side, target_side, options.k_end, shared_out, starts[i].sampled, control);
    refined_starts[i] = zoomout_dense(source_side, target_side, starts[i].sampled, shared_out, control);
  });
  control.check_cancelled();
  std::vector<SpectralMap> maps;
  std::vector<int> refined;  // the tracked map of each of `maps`
  for (size_t i = 0; i < starts.size(); ++i) {
    // A map refined twice would be finished and measured twice, for nothing.
    SpectralMap& map = refined_starts[i];
    const bool seen = std::any_of(maps.begin(), maps.end(), [&](const SpectralMap& other) {
      return same_dense_map(other.image, map.image, source.spectral_samples(), target.geodesics().topology());
    });
    if (seen) continue;
    maps.push_back(std::move(map));
    refined.push_back(starts[i].evidence.tracked_index);
  }
  clock.finish("refine");
  // A mirror image stays one when finished (it reverses handedness everywhere): the
  // handedness of the spectral maps decides which are worth finishing.
  std::vector<double> handedness(maps.size());
  for (size_t i = 0; i < maps.size(); ++i)
    handedness[i] = dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(), target.normals(),
                                                maps[i].image);
  const double best_handedness = maps.empty() ? 0 : *std::max_element(handedness.begin(), handedness.end());
  // Finishing costs as much as the spectral refinement; only the kFinishedCandidates maps
  // that pass the mirror test and whose raw curvature agrees best are finished, and only
  // finished maps compete while one is eligible. A raw map is no match for a finished one:
  // the polish tears a swapped limb's seams open, so a partial flip's curvature rises when
  // finished (SCAPE 000 -> 011: raw 0.124 against the right map's 0.136, finished 0.144
  // against 0.128).
  std::vector<std::pair<double, size_t>> by_curvature;
  const double mirror_below = mirror_threshold(best_handedness, settings.orientation_margin);
  for (size_t i = 0; i < maps.size(); ++i)
    if (handedness[i] >= mirror_below)
      by_curvature.emplace_back(curvature_disagreement(source, target, maps[i].image), i);
  std::sort(by_curvature.begin(), by_curvature.end());
  while (by_curvature.size() > kAlwaysFinished &&
         by_curvature.back().first > (1 + kFinishedCurvatureMargin) * by_curvature[0].first)
    by_curvature.pop_back();
  if (by_curvature.size() > kFinishedCandidates) by_curvature.resize(kFinishedCandidates);
  std::vector<bool> finished(maps.size(), false);
  std::vector<Finishing> finishings(maps.size());
  for (const auto& [curvature, i] : by_curvature) finished[i] = true;
  auto measure = [&](size_t i, DenseCandidate& candidate, int threads) {
    candidate.forward = maps[i].image;
    candidate.evidence = measure_dense_map(source, target, maps[i].image, maps[i].reverse_image,
                                           settings.dense_choice_sources, threads);
  };
  result.candidates.resize(maps.size());
  // The finished ones first: a finishing costs several measurings. Where all maps are
  // alike (all finished, or none), the last few share the workers. Where the finishings
  // fill whole rounds of workers, the cheap measurings run beside the last round, one
  // worker each (run after them instead, a 5K pair's two finishings and two measurings
  // took 0.045 s longer). Where they do not, a lone last finishing would run on one worker
  // while the measurings left the others idle: the finishings share the workers first, the
  // measurings after them (TOSCA 5k cat1 -> cat2, three finished and one measured: a core
  // sat idle for 0.2 s).
  std::vector<int> order;
  for (size_t i = 0; i < maps.size(); ++i)
    if (finished[i]) order.push_back(static_cast<int>(i));
  const int finishing = static_cast<int>(order.size());
  for (size_t i = 0; i < maps.size(); ++i)
    if (!finished[i]) order.push_back(static_cast<int>(i));
  auto finish_and_measure = [&](int i, int workers) {
    if (finished[i]) finish(maps[i], finishings[i], workers, false);
    result.candidates[i].tracked_index = refined[i];
    result.candidates[i].finished = finished[i];
    measure(i, result.candidates[i], workers);
  };
  const int count = static_cast<int>(order.size());
  if (finishing == count || finishing == 0 || finishing % threads != 0) {
    parallel_for_sharing(finishing, threads, [&](int k, int workers) { finish_and_measure(order[k], workers); });
    parallel_for_sharing(count - finishing, threads,
                         [&](int k, int workers) { finish_and_measure(order[finishing + k], workers); });
  } else {
    parallel_for(count, threads, [&](int k, int) { finish_and_measure(order[k], 1); });
  }
  control.check_cancelled();
  result.chosen = choose_dense_candidate(result.candidates, settings.orientation_margin, result.why);
  SpectralMap& winner = maps[result.chosen];
  if (!finished[result.chosen]) {  // no finished candidate was eligible
    finish(winner, finishings[result.chosen], settings.threads, false);
    measure(result.chosen, result.candidates[result.chosen], settings.threads);
  }
  Finishing last = finishings[result.chosen];
  clock.finish("finish");
  if (settings.rigidity.mirror_repair) result.mirror_repair_chosen = rigidity.unfold_mirrors(winner);
  // The candidates' evidence describes their maps before the spectral polish: it decided
  // the choice. Without a polish, an unfolded winner is finished again instead.
  const bool polished = zoomout_polish(source_side, target_side, options, winner, control);
  if (polished || result.mirror_repair_chosen.segments > 0) finish(winner, last, settings.threads, true);
  result.repair = last.repair;
  result.mirror_repair = last.mirror_repair;
  for (int pass = 0; pass < settings.refine_passes; ++pass)
    winner = refine_again_with(source, target, rigidity, winner, settings, control);
  result.final_polish = extend_rigidity_polish(source, target, settings.rigidity_final_iterations,
                                               settings.threads, winner, control);
  result.candidates[result.chosen].forward = winner.image;
  result.dense.forward = std::move(winner.image);
  result.dense.forward_diso = std::move(winner.residual);
  result.dense.reverse = std::move(winner.reverse_image);
  result.dense.reverse_diso = std::move(winner.reverse_residual);
  clock.finish("polish");
  return result;
}

}  // namespace isocorr
