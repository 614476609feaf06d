#include "isocorr/refinement/refinement.h"

#include <algorithm>
#include <unordered_map>
#include <utility>

#include "isocorr/matching/orientation.h"
#include "isocorr/util/error.h"
#include "isocorr/util/parallel.h"

namespace isocorr {
namespace {

// Two tracked maps that send at least this share of their common source samples to the
// same target sample end in the same place: refining both would measure one map twice.
constexpr double kSameMapShare = 0.8;

constexpr size_t kFinishedCandidates = 3;

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

// Two refined maps that send this share of the source's spectral samples to the same
// target vertex or one of its neighbours are one map: ZoomOut from two distinct tracked
// starts often ends in the same place.
bool same_dense_map(const std::vector<int>& a, const std::vector<int>& b, const std::vector<int>& samples,
                    const MeshTopology& target_topology) {
  int same = 0;
  for (const int v : samples) {
    const int x = a[v], y = b[v];
    same += x == y || std::find(target_topology.neighbours_begin(x), target_topology.neighbours_end(x), y) !=
                          target_topology.neighbours_end(x);
  }
  return !samples.empty() && same >= kSameMapShare * samples.size();
}

}  // namespace

RefinedMatch refine_and_choose(const PreprocessedShape& source, const PreprocessedShape& target,
                               const std::vector<TrackedMap>& tracked, const std::vector<int>& ranked,
                               const MatchSettings& settings, const JobControl& control) {
  if (source.spectral_basis().cols() == 0 || target.spectral_basis().cols() == 0)
    throw InputError("refinement needs the shapes' spectral basis: spectral_basis must be positive");
  std::vector<int> picked;
  for (const int index : ranked) {
    if (static_cast<int>(picked.size()) >= settings.refine_candidates) break;
    bool distinct = true;
    for (const int other : picked) distinct = distinct && !same_map(tracked[other], tracked[index]);
    if (distinct) picked.push_back(index);
  }

  auto side_of = [](const PreprocessedShape& shape) {
    return SpectralSide{&shape.spectral_basis(), &shape.geodesics().topology(), &shape.spectral_samples(),
                        &shape.spectral_eigenvalues()};
  };
  const SpectralSide source_side = side_of(source), target_side = side_of(target);
  ZoomOutOptions options = settings.zoomout;
  options.threads = settings.threads;
  RefinedMatch result;
  RigidityOptions rigidity_options = settings.rigidity;
  rigidity_options.threads = settings.threads;
  const RigidityPolish rigidity(source, target, rigidity_options);
  // Every candidate is finished before the choice, not only the winner: a right map that
  // converged less well (SCAPE 001 -> 004, 006: D_grd 0.016-0.02 against 0.010 typical)
  // lost to a turned body on heat signatures; finished, it wins (signature 0.0145 against
  // 0.0150 on 001 -> 004). The repair goes first: the rigidity polish would spread a
  // misplaced region into its surroundings.
  auto finish = [&](SpectralMap& map, OutlierRepair& repair) {
    if (settings.outlier_repair) repair = repair_outliers(source, target, map.image, settings.threads, control);
    rigidity.apply(map, control);
  };
  std::vector<SpectralMap> maps;
  std::vector<int> refined;  // the tracked map of each of `maps`
  for (const int index : picked) {
    std::vector<std::pair<int, int>> start;
    for (const SamplePair& p : tracked[index].pairs)
      start.emplace_back(source.sample_vertex(p.source_sample), image_vertex(target, p));
    SpectralMap map = zoomout(source_side, target_side, start, options, control);
    control.check_cancelled();
    // A map refined twice would be finished and measured twice, for nothing.
    const bool seen = std::any_of(maps.begin(), maps.end(), [&](const SpectralMap& other) {
      return same_dense_map(other.image, map.image, source.spectral_samples(), target.geodesics().topology());
    });
    if (seen) continue;
    maps.push_back(std::move(map));
    refined.push_back(index);
  }
  // A mirror image stays one when finished (it reverses handedness everywhere): the
  // handedness of the spectral maps decides which are worth finishing.
  std::vector<double> handedness(maps.size());
  for (size_t i = 0; i < maps.size(); ++i)
    handedness[i] = dense_orientation_agreement(source.mesh(), source.normals(), target.mesh(), target.normals(),
                                                maps[i].image);
  const double best_handedness = maps.empty() ? 0 : *std::max_element(handedness.begin(), handedness.end());
  // Finishing costs as much as the spectral refinement; only the kFinishedCandidates maps
  // within the orientation margin of the best whose raw curvature agrees best are
  // finished (a turned body's disagreement is 20-30% above the right map's before
  // finishing as after). The others compete unfinished (a partial mirror may keep 0.63 of
  // the faces, michael: finishing it would cost 1.8 s for nothing); a winner among them is
  // finished afterwards.
  std::vector<std::pair<double, size_t>> by_curvature;
  for (size_t i = 0; i < maps.size(); ++i)
    if (handedness[i] >= best_handedness - settings.orientation_margin)
      by_curvature.emplace_back(curvature_disagreement(source, target, maps[i].image), i);
  std::sort(by_curvature.begin(), by_curvature.end());
  if (by_curvature.size() > kFinishedCandidates) by_curvature.resize(kFinishedCandidates);
  std::vector<bool> finished(maps.size(), false);
  std::vector<OutlierRepair> repairs(maps.size());
  for (const auto& [curvature, i] : by_curvature) finished[i] = true;
  auto measure = [&](size_t i, DenseCandidate& candidate) {
    candidate.forward = maps[i].image;
    candidate.evidence = measure_dense_map(source, target, maps[i].image, maps[i].reverse_image,
                                           settings.dense_choice_sources, settings.threads);
  };
  result.candidates.resize(maps.size());
  for (size_t i = 0; i < maps.size(); ++i) {
    if (finished[i]) finish(maps[i], repairs[i]);
    result.candidates[i].tracked_index = refined[i];
    measure(i, result.candidates[i]);
    control.check_cancelled();
  }
  result.chosen = choose_dense_candidate(result.candidates, settings.orientation_margin, result.why);
  SpectralMap& winner = maps[result.chosen];
  if (!finished[result.chosen]) {
    finish(winner, repairs[result.chosen]);
    measure(result.chosen, result.candidates[result.chosen]);
  }
  result.repair = repairs[result.chosen];
  // The optional spectral polish of the winner starts from its spectral functional map and
  // leaves a spectral map: finish it again. The candidates' evidence describes their maps
  // before it: it decided the choice.
  const int basis_before = static_cast<int>(winner.c.rows());
  zoomout_polish(source_side, target_side, options, winner, control);
  if (static_cast<int>(winner.c.rows()) != basis_before) finish(winner, result.repair);
  result.candidates[result.chosen].forward = winner.image;
  result.dense.forward = std::move(winner.image);
  result.dense.forward_diso = std::move(winner.residual);
  result.dense.reverse = std::move(winner.reverse_image);
  result.dense.reverse_diso = std::move(winner.reverse_residual);
  return result;
}

}  // namespace isocorr
