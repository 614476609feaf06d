// isocorr-bench: runs the pairs.tsv lists of the benchmark datasets and prints, per
// dataset, flip-free %, D_grd, d_grd-dagger, Kim AUC, D_iso, seconds and peak memory per
// pair, for three variants of the settings given (default: refined and chosen by dense
// evidence; the C2F map alone, refine = none; the paper's pipeline, refine = none with the
// least-D_iso rule), then how the time grows with the vertex count. With --from-truth, the
// refinement alone, started from the ground truth: the error it adds by itself.
//
// Each pair runs in a forked child so that its peak memory is its own.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include <CLI/CLI.hpp>

#include "isocorr/diagnosis/map_tearing.h"
#include "isocorr/eval/ground_truth.h"
#include "isocorr/eval/metrics.h"
#include "isocorr/geodesic/geodesic_diameter.h"
#include "isocorr/pipeline/run_match.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/refinement/refinement.h"
#include "isocorr/transfer/landmarks.h"
#include "isocorr/util/huge_page_malloc.h"
#include "settings_flags.h"

namespace {

using namespace isocorr;

struct RuleOutcome {
  double d_grd = 0, d_grd_max = 0, kim_auc = 0, diso = 0, mirrored = -1;
  double d_grd_precise = -1;  // of the map's precise map (precise_map.h); -1: not measured
  int flip_free = 0, tracked = 0, chosen_rank = 0;
  int suspect = 0;  // the result's verdict (diagnosis/verdict.h)
};

// One refined candidate of the "as set" run: its dense evidence and its ground-truth score.
struct CandidateOutcome {
  double orientation = 0, neighbourhood = 0, distortion = 0, round_trip = 0, signature = 0, curvature = 0, d_grd = 0;
  double distortion_max = 0;  // the largest mean distortion from one sample
  int torn_pairs = 0, torn_samples = 0;  // measure_map_tearing (diagnosis/map_tearing.h)
  double score = 0;        // choice_score: what the choice minimises
  double from_chosen = 0;  // mean geodesic distance from the chosen candidate's map, / diameter
  int flip_free = 0, chosen = 0, finished = 0, mirrored = 0;
};

// What each pair runs and prints.
struct RunOptions {
  int points = 1000;
  bool as_set_only = false;  // skip the C2F and paper variants
  bool candidates = false;   // score every refined candidate too
  bool from_truth = false;   // the refinement alone, from the ground truth (implies as_set_only)
  int truth_landmarks = 0;   // landmarks per pair taken from the ground truth
  bool profile = false;      // each stage's wall and CPU time and the peak memory, and the pair again with its shapes cached
};

struct PairOutcome {
  bool ok = false;
  int vertices = 0;
  double seconds = 0, peak_mb = 0;
  std::array<RuleOutcome, 3> variants;  // as set, C2F only, paper
  std::vector<CandidateOutcome> candidates;  // with --candidates
  std::vector<StageTiming> stages;  // with --profile: the match's stages, the refine stage's steps after it
  double cached_seconds = -1;       // with --profile: the match again on the same preprocessed shapes
  std::string error;
};

RuleOutcome score_map(const std::vector<int>& forward, const TriangleMesh& target, const FastMarching& geodesics,
                      double diameter, const GroundTruth& truth, int points) {
  EvaluationOptions options;
  options.max_points = points;
  const GroundTruthScore s = score_against_ground_truth(target, geodesics, diameter, forward, truth, options);
  RuleOutcome out;
  out.d_grd = s.mean_error;
  out.d_grd_max = s.max_error;
  out.kim_auc = s.kim_auc;
  out.mirrored = s.mirrored_fraction;
  out.flip_free = s.flip_free;
  return out;
}

RuleOutcome score(const MatchResult& result, const TriangleMesh& target, const FastMarching& geodesics,
                  double diameter, const GroundTruth& truth, int points) {
  RuleOutcome out = score_map(result.output.forward, target, geodesics, diameter, truth, points);
  out.diso = result.quality.diso;
  out.tracked = static_cast<int>(result.diagnostics.tracking.maps.size());
  out.chosen_rank = result.diagnostics.tracking.maps[result.diagnostics.tracking.chosen].level0_rank;
  out.suspect = result.verdict.suspect;
  return out;
}

// `count` landmarks from the ground truth, as a user would give them: at the source's
// extremities (hands, feet, head first), each with the truth's image of the ground-truth
// point nearest it on the source.
std::vector<Landmark> landmarks_from_truth(const PreprocessedShape& source, const GroundTruth& truth, int count) {
  std::vector<Landmark> landmarks;
  for (const int extremity : source.saliency().extremities) {
    if (static_cast<int>(landmarks.size()) >= count) break;
    const std::vector<float> distance = source.geodesics().distance_field(extremity);
    int nearest = -1;
    for (size_t k = 0; k < truth.source.size(); ++k) {
      if (truth.source[k] < 0 || truth.target[k] < 0) continue;
      const int clean = source.clean().input_to_clean[truth.source[k]];
      if (nearest < 0 || distance[clean] < distance[source.clean().input_to_clean[truth.source[nearest]]])
        nearest = static_cast<int>(k);
    }
    if (nearest < 0) break;
    const Landmark landmark{truth.source[nearest], truth.target[nearest]};
    std::vector<Landmark> with = landmarks;
    with.push_back(landmark);
    if (!find_landmark_problem(with)) landmarks = std::move(with);
  }
  return landmarks;
}

// Runs in the child: the whole job as a user would run it, then scoring (not timed).
PairOutcome run_pair(const std::string& dataset, const BenchmarkPair& pair, MatchSettings settings,
                     const RunOptions& run) {
  const int points = run.points;
  PairOutcome outcome;
  const auto start = std::chrono::steady_clock::now();
  const LoadedMesh source = load_mesh(pair.source_path);
  const LoadedMesh target = load_mesh(pair.target_path);
  MeshPairShapes shapes(source.mesh, target.mesh);  // the other variants reuse the preprocessing
  if (run.truth_landmarks > 0)
    settings.landmarks =
        landmarks_from_truth(*shapes.shape(ShapeRole::kSource, settings.preprocess, {}),
                             load_ground_truth(dataset, pair, source.mesh.num_vertices(), target.mesh.num_vertices()),
                             run.truth_landmarks);
  const MatchResult as_set = run_match(shapes, settings);
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (run.profile) {
    outcome.stages = as_set.timings.stages;
    for (StageTiming step : as_set.timings.refine_steps) {
      step.stage = "refine/" + step.stage;
      outcome.stages.push_back(step);
    }
    // What a server that has both shapes cached runs: the per-pair work alone.
    const auto again = std::chrono::steady_clock::now();
    run_match(shapes, settings);
    outcome.cached_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - again).count();
  }
  MatchResult c2f, paper;
  if (!run.as_set_only) {
    settings.refine = RefineMethod::kNone;
    c2f = run_match(shapes, settings);
    settings.selection = SelectionRule::kLeastDistortion;
    paper = run_match(shapes, settings);
  }

  const GroundTruth truth = load_ground_truth(dataset, pair, source.mesh.num_vertices(), target.mesh.num_vertices());
  const MeshTopology topology(target.mesh);
  const FastMarching geodesics(target.mesh, topology);
  const double diameter = estimate_geodesic_diameter(geodesics);
  const MatchResult* results[] = {&as_set, &c2f, &paper};
  for (int i = 0; i < (run.as_set_only ? 1 : 3); ++i) outcome.variants[i] = score(*results[i], target.mesh, geodesics, diameter, truth, points);
  {
    EvaluationOptions options;
    options.max_points = points;
    options.precise = &as_set.output.forward_precise;
    outcome.variants[0].d_grd_precise =
        score_against_ground_truth(target.mesh, geodesics, diameter, as_set.output.forward, truth, options).mean_error;
  }
  if (run.candidates) {
    EvaluationOptions options;
    options.max_points = points;
    const auto& refined = as_set.diagnostics.refinement;
    // The chosen candidate's map as a "truth": how far each other candidate lies from it.
    GroundTruth chosen_map;
    if (!refined.candidates.empty()) {
      chosen_map.target = refined.candidates[refined.chosen].forward;
      for (size_t v = 0; v < chosen_map.target.size(); ++v) chosen_map.source.push_back(static_cast<int>(v));
    }
    const auto source_shape = shapes.shape(ShapeRole::kSource, settings.preprocess, {});
    const auto target_shape = shapes.shape(ShapeRole::kTarget, settings.preprocess, {});
    for (size_t i = 0; i < refined.candidates.size(); ++i) {
      const DenseCandidate& c = refined.candidates[i];
      std::vector<int> clean_forward(source_shape->mesh().num_vertices());
      for (size_t v = 0; v < clean_forward.size(); ++v)
        clean_forward[v] = target_shape->clean().input_to_clean[c.forward[source_shape->clean().clean_to_input[v]]];
      const MapTearing tearing = measure_map_tearing(*source_shape, *target_shape, clean_forward);
      const GroundTruthScore s = score_against_ground_truth(target.mesh, geodesics, diameter, c.forward, truth, options);
      CandidateOutcome o{c.evidence.orientation, c.evidence.neighbourhood_orientation, c.evidence.distortion,
                         c.evidence.round_trip, c.evidence.signature_disagreement, c.evidence.curvature_disagreement,
                         s.mean_error};
      o.score = c.score;
      o.distortion_max = c.evidence.distortion_max;
      o.torn_pairs = tearing.torn_pairs, o.torn_samples = tearing.torn_samples;
      o.from_chosen =
          score_against_ground_truth(target.mesh, geodesics, diameter, c.forward, chosen_map, options).mean_error;
      o.flip_free = s.flip_free;
      o.chosen = static_cast<int>(i) == refined.chosen;
      o.finished = c.finished;
      o.mirrored = c.mirrored;
      outcome.candidates.push_back(o);
    }
  }
  outcome.vertices = source.mesh.num_vertices();
  outcome.ok = true;
  return outcome;
}

// Runs in the child: the refinement alone (as the chosen candidate is refined), started
// from the ground-truth pairs instead of a tracked map, timed with the preprocessing.
PairOutcome run_pair_from_truth(const std::string& dataset, const BenchmarkPair& pair, const MatchSettings& settings,
                                int points) {
  settings.validate();
  PairOutcome outcome;
  const LoadedMesh source = load_mesh(pair.source_path);
  const LoadedMesh target = load_mesh(pair.target_path);
  const GroundTruth truth = load_ground_truth(dataset, pair, source.mesh.num_vertices(), target.mesh.num_vertices());
  const auto start = std::chrono::steady_clock::now();
  MeshPairShapes shapes(source.mesh, target.mesh);
  const auto s = shapes.shape(ShapeRole::kSource, settings.preprocess, {});
  const auto t = shapes.shape(ShapeRole::kTarget, settings.preprocess, {});
  const CleanMesh& sc = s->clean();
  const CleanMesh& tc = t->clean();
  std::vector<std::pair<int, int>> pairs;
  for (size_t k = 0; k < truth.source.size(); ++k)
    if (truth.source[k] >= 0 && truth.target[k] >= 0)
      pairs.emplace_back(sc.input_to_clean[truth.source[k]], tc.input_to_clean[truth.target[k]]);
  const SpectralMap map = refine_from_pairs(*s, *t, pairs, settings);
  std::vector<int> forward(source.mesh.num_vertices());
  for (size_t i = 0; i < forward.size(); ++i) forward[i] = tc.clean_to_input[map.image[sc.input_to_clean[i]]];
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const MeshTopology topology(target.mesh);
  const FastMarching geodesics(target.mesh, topology);
  outcome.variants[0] = score_map(forward, target.mesh, geodesics, estimate_geodesic_diameter(geodesics), truth, points);
  outcome.vertices = source.mesh.num_vertices();
  outcome.ok = true;
  return outcome;
}


std::string serialise(const PairOutcome& o) {
  std::ostringstream out;
  out.precision(9);
  out << o.ok << ' ' << o.vertices << ' ' << o.seconds;
  for (const RuleOutcome& r : o.variants)
    out << ' ' << r.d_grd << ' ' << r.d_grd_precise << ' ' << r.d_grd_max << ' ' << r.kim_auc << ' ' << r.diso << ' ' << r.mirrored
        << ' ' << r.flip_free << ' ' << r.tracked << ' ' << r.chosen_rank << ' ' << r.suspect;
  out << ' ' << o.candidates.size();
  for (const CandidateOutcome& c : o.candidates)
    out << ' ' << c.orientation << ' ' << c.neighbourhood << ' ' << c.distortion << ' ' << c.round_trip << ' '
        << c.signature << ' ' << c.curvature << ' ' << c.d_grd << ' ' << c.score << ' ' << c.from_chosen << ' '
        << c.flip_free << ' ' << c.chosen << ' ' << c.finished << ' ' << c.mirrored << ' ' << c.distortion_max << ' ' << c.torn_pairs << ' ' << c.torn_samples;
  out << ' ' << o.stages.size();
  for (const StageTiming& t : o.stages) out << ' ' << t.stage << ' ' << t.seconds << ' ' << t.cpu_seconds << ' ' << t.peak_mb;
  out << ' ' << o.cached_seconds;
  out << ' ' << o.error;
  return out.str();
}

PairOutcome deserialise(const std::string& line) {
  std::istringstream in(line);
  PairOutcome o;
  in >> o.ok >> o.vertices >> o.seconds;
  for (RuleOutcome& r : o.variants)
    in >> r.d_grd >> r.d_grd_precise >> r.d_grd_max >> r.kim_auc >> r.diso >> r.mirrored >> r.flip_free >> r.tracked >>
        r.chosen_rank >> r.suspect;
  size_t count = 0;
  in >> count;
  o.candidates.resize(count);
  for (CandidateOutcome& c : o.candidates)
    in >> c.orientation >> c.neighbourhood >> c.distortion >> c.round_trip >> c.signature >> c.curvature >> c.d_grd >>
        c.score >> c.from_chosen >> c.flip_free >> c.chosen >> c.finished >> c.mirrored >> c.distortion_max >> c.torn_pairs >> c.torn_samples;
  in >> count;
  o.stages.resize(count);
  for (StageTiming& t : o.stages) in >> t.stage >> t.seconds >> t.cpu_seconds >> t.peak_mb;
  in >> o.cached_seconds;
  std::getline(in >> std::ws, o.error);
  return o;
}

PairOutcome run_in_child(const std::string& dataset, const BenchmarkPair& pair, const MatchSettings& settings,
                         const RunOptions& run) {
  int fds[2];
  if (pipe(fds) != 0) {
    PairOutcome failed;
    failed.error = "pipe failed";
    return failed;
  }
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    PairOutcome outcome;
    try {
      outcome = run.from_truth ? run_pair_from_truth(dataset, pair, settings, run.points)
                               : run_pair(dataset, pair, settings, run);
    } catch (const std::exception& e) {
      outcome.error = e.what();
    }
    const std::string line = serialise(outcome) + "\n";
    if (write(fds[1], line.data(), line.size()) < 0) _exit(2);
    _exit(0);
  }
  close(fds[1]);
  std::string line;
  char buffer[4096];
  for (ssize_t got; (got = read(fds[0], buffer, sizeof buffer)) > 0;) line.append(buffer, got);
  close(fds[0]);
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  PairOutcome outcome;
  if (line.empty()) outcome.error = "child died";
  else outcome = deserialise(line);
  outcome.peak_mb = usage.ru_maxrss / 1024.0;
  return outcome;
}

// One pair's stages: wall and CPU seconds, and the process's peak memory once each ended
// (the two preprocessings run at once: the target's time is what was left of it).
void print_profile(const PairOutcome& o) {
  for (const StageTiming& t : o.stages)
    std::printf("    stage %-34s %7.2f s wall %7.2f s CPU  peak %6.0f MB\n", t.stage.c_str(), t.seconds, t.cpu_seconds,
                t.peak_mb);
  if (o.cached_seconds >= 0) std::printf("    with both shapes cached: %.2f s\n", o.cached_seconds);
}

// Per stage, the mean over a set's pairs; and the mean time of a cached pair.
void print_profile_means(const std::vector<PairOutcome>& outcomes) {
  std::vector<std::string> order;
  std::map<std::string, std::array<double, 3>> sums;  // wall, CPU, pairs
  double cached = 0;
  int pairs = 0;
  for (const auto& o : outcomes) {
    if (!o.ok) continue;
    ++pairs;
    cached += o.cached_seconds;
    for (const StageTiming& t : o.stages) {
      if (!sums.count(t.stage)) order.push_back(t.stage);
      auto& sum = sums[t.stage];
      sum[0] += t.seconds, sum[1] += t.cpu_seconds, sum[2] += 1;
    }
  }
  if (!pairs) return;
  std::printf("  profile (mean per pair): with both shapes cached %.2f s\n", cached / pairs);
  for (const std::string& stage : order) {
    const auto& sum = sums[stage];
    std::printf("    %-34s %7.3f s wall %7.3f s CPU\n", stage.c_str(), sum[0] / sum[2], sum[1] / sum[2]);
  }
}

// How well the verdict tells wrong maps (not flip-free) from right ones: recall is the share
// of wrong maps flagged suspect, precision the share of flagged maps that are wrong.
void print_verdict_row(const std::vector<PairOutcome>& outcomes, int variant) {
  int wrong = 0, wrong_flagged = 0, right = 0, right_flagged = 0;
  for (const auto& o : outcomes) {
    if (!o.ok) continue;
    const RuleOutcome& r = o.variants[variant];
    if (r.flip_free) ++right, right_flagged += r.suspect;
    else ++wrong, wrong_flagged += r.suspect;
  }
  const int flagged = wrong_flagged + right_flagged;
  std::printf("  %-12s suspect: %d of %d wrong maps (recall %s), %d of %d right maps (%.1f%%); precision %s\n", "",
              wrong_flagged, wrong, wrong ? std::to_string(100 * wrong_flagged / wrong).append("%").c_str() : "-",
              right_flagged, right, right ? 100.0 * right_flagged / right : 0.0,
              flagged ? std::to_string(100 * wrong_flagged / flagged).append("%").c_str() : "-");
}

void print_rule_row(const char* rule, const std::vector<PairOutcome>& outcomes, int variant) {
  int ok = 0, flip_free = 0;
  double d_grd = 0, d_precise = 0, d_max = 0, auc = 0, diso = 0;
  for (const auto& o : outcomes) {
    if (!o.ok) continue;
    const RuleOutcome& r = o.variants[variant];
    ++ok;
    auc += r.kim_auc;
    diso += r.diso;
    if (r.flip_free) ++flip_free, d_grd += r.d_grd, d_precise += r.d_grd_precise, d_max += r.d_grd_max;
  }
  if (!ok) return;
  std::printf("  %-12s flip-free %3d/%-3d (%5.1f%%)  D_grd(flip-free) %.4f  d_grd-dagger %.4f  Kim AUC %.3f  D_iso %.4f",
              rule, flip_free, ok, 100.0 * flip_free / ok, flip_free ? d_grd / flip_free : NAN,
              flip_free ? d_max / flip_free : NAN, auc / ok, diso / ok);
  if (variant == 0 && flip_free && d_precise >= 0) std::printf("  precise D_grd(flip-free) %.4f", d_precise / flip_free);
  std::printf("\n");
  print_verdict_row(outcomes, variant);
}

// Per mesh, the pairs of the first variant it takes part in (as source or target): on a
// set's mean error a few meshes in hard poses can weigh more than any setting (SCAPE's
// mesh007, knees drawn to the chest, is in 8 of its 12 worst flip-free pairs).
void print_by_mesh(const std::vector<std::pair<std::string, std::string>>& names,
                   const std::vector<PairOutcome>& outcomes) {
  struct Tally {
    int pairs = 0, flip_free = 0;
    double d_grd = 0;
  };
  std::map<std::string, Tally> by_mesh;
  for (size_t i = 0; i < outcomes.size(); ++i) {
    if (!outcomes[i].ok) continue;
    const RuleOutcome& r = outcomes[i].variants[0];
    for (const std::string& mesh : {names[i].first, names[i].second}) {
      Tally& t = by_mesh[mesh];
      ++t.pairs;
      if (r.flip_free) ++t.flip_free, t.d_grd += r.d_grd;
    }
  }
  std::vector<std::pair<double, std::string>> order;
  for (const auto& [mesh, t] : by_mesh) order.push_back({t.flip_free ? t.d_grd / t.flip_free : INFINITY, mesh});
  std::sort(order.rbegin(), order.rend());  // worst first
  std::printf("  by mesh (pairs it is in; worst first):\n");
  for (const auto& [mean, mesh] : order) {
    const Tally& t = by_mesh[mesh];
    std::printf("    %-16s %3d pairs  flip-free %3d  D_grd(flip-free) %.4f\n", mesh.c_str(), t.pairs, t.flip_free,
                t.flip_free ? mean : NAN);
  }
}

}  // namespace

int main(int argc, char** argv) {
  isocorr::restart_with_huge_page_malloc(argv);  // as isocorr and isocorr-server run
  CLI::App app{"isocorr-bench: accuracy and speed on the benchmark datasets' pairs.tsv lists"};
  std::vector<std::string> datasets;
  std::string data_root = "../shared/data", protocol;
  int limit = 0;
  RunOptions run;
  MatchSettings settings;
  app.add_option("datasets", datasets, "dataset folders under --data (default: tosca_hires faust_reg6890 scape)");
  app.add_option("--data", data_root, "root of the benchmark data")->capture_default_str();
  app.add_option("--limit", limit, "at most this many pairs per dataset (0 = all)")->capture_default_str();
  app.add_option("--protocol", protocol, "only pairs whose protocol column contains this");
  app.add_option("--points", run.points, "ground-truth points scored per pair")->capture_default_str();
  app.add_flag("--as-set-only", run.as_set_only, "score only the settings given (skip the C2F and paper variants)");
  bool by_mesh = false;
  app.add_flag("--by-mesh", by_mesh, "after each dataset, the mean error of the pairs each mesh takes part in, worst first");
  app.add_flag("--candidates", run.candidates, "print every refined candidate's dense evidence and ground-truth score");
  app.add_flag("--profile", run.profile,
               "print each stage's wall and CPU seconds and the peak memory after it, and time the pair again with "
               "both shapes preprocessed (a server's cached pair)");
  app.add_flag("--from-truth", run.from_truth,
               "refine from the ground-truth correspondences instead of the tracked maps (the error the "
               "refinement adds by itself; implies --as-set-only)");
  app.add_option("--truth-landmarks", run.truth_landmarks,
                 "give each pair this many landmarks from the ground truth, at the source's extremities (the "
                 "source is then preprocessed before the target, not beside it)")
      ->check(CLI::Range(0, 10));
  isocorr::cli::LandmarksFile landmarks_file;
  isocorr::cli::add_match_settings_flags(app, settings, landmarks_file);
  CLI11_PARSE(app, argc, argv);
  run.as_set_only = run.as_set_only || run.from_truth;
  const char* first_label = run.from_truth ? "from truth" : "as set";
  if (datasets.empty()) datasets = {"tosca_hires", "faust_reg6890", "scape"};

  std::printf("flip-free rule: mean error < 0.1 of the diameter and at most 5%% of points nearer their mirror image "
              "(with symmetry GT), else at most 5%% of points off by more than 0.2\n");
  std::vector<std::pair<int, double>> scaling;
  for (const auto& name : datasets) {
    const std::string dir = data_root + "/" + name;
    if (!std::filesystem::exists(dir + "/pairs.tsv")) {
      std::printf("%s: no pairs.tsv under %s, skipped\n", name.c_str(), dir.c_str());
      continue;
    }
    std::vector<PairOutcome> outcomes;
    std::vector<std::pair<std::string, std::string>> names;  // each outcome's source and target stems
    int taken = 0;
    for (const auto& pair : read_pairs_tsv(dir)) {
      if (!protocol.empty() && pair.protocol.find(protocol) == std::string::npos) continue;
      if (limit > 0 && taken >= limit) break;
      ++taken;
      const PairOutcome o = run_in_child(dir, pair, settings, run);
      const auto stem = [](const std::string& p) { return std::filesystem::path(p).stem().string(); };
      if (o.ok) {
        std::printf("%-14s %-12s -> %-12s V=%6d %7.2f s %6.0f MB", name.c_str(), stem(pair.source_path).c_str(),
                    stem(pair.target_path).c_str(), o.vertices, o.seconds, o.peak_mb);
        const char* labels[] = {first_label, "C2F", "paper"};
        for (int i = 0; i < (run.as_set_only ? 1 : 3); ++i) {
          std::printf(" | %s: %s D_grd %.4f", labels[i], o.variants[i].flip_free ? "ok  " : "FLIP", o.variants[i].d_grd);
          if (o.variants[i].d_grd_precise >= 0) std::printf(" precise %.4f", o.variants[i].d_grd_precise);
          if (!run.from_truth) std::printf(" #%d", o.variants[i].chosen_rank + 1);  // the tracked map's level-0 rank
          if (o.variants[i].suspect) std::printf(" SUSPECT");
        }
        std::printf("\n");
        for (const CandidateOutcome& c : o.candidates)
          std::printf("    candidate%s %s%s orientation %.3f neighbourhood %.3f distortion %.4f (max %.4f) round trip %.4f"
                      " torn pairs %d samples %d signature %.4f curvature %.4f score %.5f from chosen %.4f | %s D_grd %.4f\n",
                      c.chosen ? "*" : " ", c.finished ? "finished" : "raw     ", c.mirrored ? " mirrored" : "",
                      c.orientation, c.neighbourhood, c.distortion, c.distortion_max, c.round_trip, c.torn_pairs, c.torn_samples, c.signature, c.curvature, c.score,
                      c.from_chosen, c.flip_free ? "ok  " : "FLIP", c.d_grd);
        if (run.profile) print_profile(o);
        scaling.push_back({o.vertices, o.seconds});
      } else {
        std::printf("%-14s %-12s -> %-12s FAILED: %s\n", name.c_str(), stem(pair.source_path).c_str(),
                    stem(pair.target_path).c_str(), o.error.c_str());
      }
      std::fflush(stdout);
      outcomes.push_back(o);
      names.push_back({stem(pair.source_path), stem(pair.target_path)});
    }
    double seconds = 0, peak = 0;
    int ok = 0;
    for (const auto& o : outcomes)
      if (o.ok) ++ok, seconds += o.seconds, peak = std::max(peak, o.peak_mb);
    std::printf("== %s: %d pairs, %.2f s per pair, peak %.0f MB\n", name.c_str(), ok, ok ? seconds / ok : 0.0, peak);
    print_rule_row(first_label, outcomes, 0);
    if (run.profile) print_profile_means(outcomes);
    if (by_mesh) print_by_mesh(names, outcomes);
    if (run.as_set_only) continue;
    print_rule_row("C2F only", outcomes, 1);
    print_rule_row("paper", outcomes, 2);
  }
  // Growth with size: seconds / (V log V) should stay flat if cost grows like V log V.
  std::map<int, std::pair<double, int>> by_size;
  for (auto [v, s] : scaling) by_size[v].first += s, by_size[v].second++;
  std::printf("== scaling (mean seconds per pair by vertex count)\n");
  for (auto& [v, acc] : by_size) {
    const double s = acc.first / acc.second;
    std::printf("  V=%6d  %7.2f s  %.3f us per V log2 V\n", v, s, 1e6 * s / (v * std::log2(v)));
  }
  return 0;
}
