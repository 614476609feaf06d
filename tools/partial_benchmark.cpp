// isocorr-bench-partial: part matching on partial shapes cut from benchmark meshes.
//
// For each pair of a dataset's pairs.tsv, the source is cut (a geodesic ball, a plane, a
// few holes; cut_partial_shape), matched with method = part to the full target in its
// other pose, and scored on the ground truth carried through the cut's index map. With
// --cut-target the target loses a geodesic ball too (the general setting, --method ravac),
// and points whose true image was cut away are not scored. The cut shapes exist only in
// memory: the data's licences forbid copies.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <optional>

#include <CLI/CLI.hpp>

#include "isocorr/eval/ground_truth.h"
#include "isocorr/eval/metrics.h"
#include "isocorr/geodesic/geodesic_diameter.h"
#include "isocorr/pipeline/run_match.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/partial/part_matching.h"
#include "isocorr/partial/partial_cut.h"
#include "isocorr/partial/partial_refinement.h"
#include "isocorr/util/kd_tree.h"
#include "isocorr/util/huge_page_malloc.h"
#include "settings_flags.h"

namespace {

using namespace isocorr;

// The cuts every pair gets: one of each kind, keeping 50-80% of the area.
const CutSpec kCuts[] = {
    {CutKind::kGeodesicBall, 0.7, 1, 1},
    {CutKind::kGeodesicBall, 0.55, 1, 2},
    {CutKind::kPlane, 0.6, 1, 3},
    {CutKind::kHoles, 0.8, 3, 4},
};
const char* const kCutNames[] = {"ball70", "ball55", "plane", "holes"};

// The ground truth as a map of every part vertex (clean numbering): a vertex without a true
// image takes that of the nearest vertex (in space) that has one.
std::vector<int> dense_truth(const PreprocessedShape& part, const PreprocessedShape& target, const GroundTruth& truth) {
  const CleanMesh& pc = part.clean();
  const CleanMesh& tc = target.clean();
  std::vector<int> image(pc.mesh.num_vertices(), -1);
  for (size_t k = 0; k < truth.source.size(); ++k) image[pc.input_to_clean[truth.source[k]]] = tc.input_to_clean[truth.target[k]];
  std::vector<int> known;
  for (int v = 0; v < static_cast<int>(image.size()); ++v)
    if (image[v] >= 0) known.push_back(v);
  if (known.empty()) return image;
  const KdTree with_truth(pc.mesh.vertices, known);
  std::vector<int> filled = image;
  for (int v = 0; v < static_cast<int>(image.size()); ++v)
    if (image[v] < 0) filled[v] = image[with_truth.nearest(pc.mesh.vertices[v])];
  return filled;
}

struct Tally {
  int pairs = 0, right = 0;
  double kim = 0, d_grd = 0, auc = 0, coverage = 0, seconds = 0, matched_share = 0;
};

void print_tally(const char* name, const Tally& t) {
  const int r = std::max(1, t.right);
  std::printf("== %s: right %d/%d (%.1f%%); on those: Kim %.4f  D_grd %.4f  Kim AUC %.3f  coverage %.2f  "
              "target matched %.0f%%; %.2f s per pair\n",
              name, t.right, t.pairs, 100.0 * t.right / std::max(1, t.pairs), t.kim / r, t.d_grd / r, t.auc / r,
              t.coverage / r, 100 * t.matched_share / r, t.seconds / std::max(1, t.pairs));
}

}  // namespace

int main(int argc, char** argv) {
  isocorr::restart_with_huge_page_malloc(argv);  // as isocorr and isocorr-server run
  CLI::App app{"isocorr-bench-partial: part matching on shapes cut from the benchmark meshes"};
  std::vector<std::string> datasets;
  std::string data_root = "../shared/data";
  int limit = 3, points = 1000;
  double target_keep = 0;
  bool candidates = false;
  std::vector<std::string> cut_names;
  MatchSettings settings;
  settings.method = MatchMethod::kPart;
  app.add_option("datasets", datasets, "dataset folders under --data (default: faust_5k scape tosca_isometric_5k)");
  app.add_option("--data", data_root, "root of the benchmark data")->capture_default_str();
  app.add_option("--limit", limit, "pairs per dataset (each cut 4 ways)")->capture_default_str();
  app.add_option("--points", points, "ground-truth points scored per pair")->capture_default_str();
  app.add_option("--cut-target", target_keep,
                 "also cut a geodesic ball from the target, keeping this share of its area (0: keep it whole)")
      ->check(CLI::Range(0.0, 0.95));
  app.add_flag("--candidates", candidates,
               "also score every dense candidate of the part search against the ground truth (* = chosen)");
  app.add_option("--cuts", cut_names, "run only these cuts (ball70 ball55 plane holes; default all)");
  isocorr::cli::LandmarksFile landmarks_file;
  isocorr::cli::add_match_settings_flags(app, settings, landmarks_file);
  CLI11_PARSE(app, argc, argv);
  if (datasets.empty()) datasets = {"faust_5k", "scape", "tosca_isometric_5k"};

  std::printf("right: mean error < 0.1 of the diameter and < 10%% of points nearer their mirror image; "
              "Kim error = geodesic error / sqrt(target area); coverage: SHREC'20, 100 seeds, of the cells the true image reaches\n");
  Tally all;
  for (const auto& name : datasets) {
    const std::string dir = data_root + "/" + name;
    if (!std::filesystem::exists(dir + "/pairs.tsv")) {
      std::printf("%s: no pairs.tsv under %s, skipped\n", name.c_str(), dir.c_str());
      continue;
    }
    Tally tally;
    int taken = 0;
    for (const auto& pair : read_pairs_tsv(dir)) {
      if (limit > 0 && taken++ >= limit) break;
      const LoadedMesh source = load_mesh(pair.source_path);
      const LoadedMesh target = load_mesh(pair.target_path);
      const GroundTruth truth =
          load_ground_truth(dir, pair, source.mesh.num_vertices(), target.mesh.num_vertices());
      std::optional<PartialShape> target_part;
      if (target_keep > 0) target_part = cut_partial_shape(target.mesh, {CutKind::kGeodesicBall, target_keep, 1, 7});
      const TriangleMesh& target_mesh = target_part ? target_part->mesh : target.mesh;
      const MeshTopology topology(target_mesh);
      const FastMarching geodesics(target_mesh, topology);
      const double diameter = estimate_geodesic_diameter(geodesics);
      for (size_t c = 0; c < std::size(kCuts); ++c) {
        const CutSpec& cut = kCuts[c];
        if (!cut_names.empty() && std::find(cut_names.begin(), cut_names.end(), kCutNames[c]) == cut_names.end())
          continue;
        const auto stem = [](const std::string& p) { return std::filesystem::path(p).stem().string(); };
        std::printf("%-18s %-12s -> %-12s %-5s", name.c_str(), stem(pair.source_path).c_str(),
                    stem(pair.target_path).c_str(), cut_kind_name(cut.kind));
        try {
          const PartialShape part = cut_partial_shape(source.mesh, cut);
          const auto start = std::chrono::steady_clock::now();
          MeshPairShapes shapes(part.mesh, target_mesh);
          const MatchResult result = run_match(shapes, settings);
          const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          EvaluationOptions options;
          options.max_points = points;
          const GroundTruth part_truth =
              ground_truth_of_parts(truth, part, source.mesh.num_vertices(), target_part ? &*target_part : nullptr,
                                    target.mesh.num_vertices());
          const GroundTruthScore s =
              score_against_ground_truth(target_mesh, geodesics, diameter, result.output.forward, part_truth, options);
          const bool right = s.mean_error < 0.1 && s.mirrored_fraction < 0.1;
          const double covered =
              coverage_of_true_image(target_mesh, geodesics, result.output.forward, part_truth.target, 100);
          std::printf(" kept %3.0f%% V=%5d %6.2f s | %s D_grd %.4f Kim %.4f AUC %.3f mirrored %.2f coverage %.2f "
                      "matched %.0f%%\n",
                      100 * part.kept_area, part.mesh.num_vertices(), seconds, right ? "ok   " : "WRONG",
                      s.mean_error, s.mean_kim_error, s.kim_auc, s.mirrored_fraction, covered,
                      100 * result.quality.target_matched_share);
          if (candidates) {
            for (size_t i = 0; i < result.diagnostics.part.candidates.size(); ++i) {
              const PartCandidate& pc = result.diagnostics.part.candidates[i];
              const GroundTruthScore cs =
                  score_against_ground_truth(target_mesh, geodesics, diameter, pc.forward, part_truth, options);
              std::printf("   %c%c candidate %2zu: orientation %.2f curvature %.4f covered %.2f kappa %.3f distortion %.4f "
                          "extremities %.4f | D_grd %.4f mirrored %.2f\n",
                          pc.kept ? '*' : ' ', pc.finalist ? 'f' : ' ', i, pc.orientation,
                          pc.curvature, pc.covered, pc.scale, pc.distortion, pc.level0_distortion, cs.mean_error,
                          cs.mirrored_fraction);
            }
            // How the choice's measures judge the truth itself: a truth that loses to the chosen
            // map on them is a failure of the measures, one that wins a failure of the search.
            const auto part_shape = shapes.shape(ShapeRole::kSource, settings.preprocess, {});
            const auto target_shape = shapes.shape(ShapeRole::kTarget, settings.preprocess, {});
            const std::vector<int> truth_map = dense_truth(*part_shape, *target_shape, part_truth);
            std::vector<int> chosen(part_shape->mesh().num_vertices());
            for (size_t v = 0; v < chosen.size(); ++v)
              chosen[v] = target_shape->clean().input_to_clean[result.output.forward[part_shape->clean().clean_to_input[v]]];
            std::vector<PartMapEvidence> judged =
                measure_part_maps(*part_shape, *target_shape, {&truth_map}, settings.threads);
            const std::vector<int> refined_truth =
                refine_part_map_spectrally(*part_shape, *target_shape, judged[0].scale, settings.zoomout, truth_map);
            for (const PartMapEvidence& e :
                 measure_part_maps(*part_shape, *target_shape, {&refined_truth, &chosen}, settings.threads))
              judged.push_back(e);
            std::vector<int> refined_in_files(part.mesh.num_vertices());
            for (size_t v = 0; v < refined_in_files.size(); ++v)
              refined_in_files[v] = target_shape->clean().clean_to_input[refined_truth[part_shape->clean().input_to_clean[v]]];
            const GroundTruthScore refined_score =
                score_against_ground_truth(target_mesh, geodesics, diameter, refined_in_files, part_truth, options);
            const char* const names[] = {"ground truth", "truth refined", "chosen map"};
            for (int j = 0; j < 3; ++j)
              std::printf("   %-13s: orientation %.2f curvature %.4f kappa %.3f distortion %.4f%s\n", names[j],
                          judged[j].orientation, judged[j].curvature, judged[j].scale, judged[j].distortion,
                          j == 1 ? (" | D_grd " + std::to_string(refined_score.mean_error)).c_str() : "");
            for (const std::string& note : result.summary().notes)
              if (note.find("map kept") != std::string::npos) std::printf("   %s\n", note.c_str());  // part or whole, and why
          }
          for (Tally* t : {&tally, &all}) {
            ++t->pairs;
            t->seconds += seconds;
            if (!right) continue;
            ++t->right;
            t->kim += s.mean_kim_error, t->d_grd += s.mean_error, t->auc += s.kim_auc, t->coverage += covered;
            t->matched_share += result.quality.target_matched_share;
          }
        } catch (const std::exception& e) {
          std::printf(" FAILED: %s\n", e.what());
          ++tally.pairs, ++all.pairs;
        }
        std::fflush(stdout);
      }
    }
    print_tally(name.c_str(), tally);
  }
  if (datasets.size() > 1) print_tally("all", all);
  return 0;
}
