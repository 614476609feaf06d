// `isocorr eval SOURCE TARGET MAP [--dataset DIR] [--gt-kind K]`: scores a map against
// ground truth.
#include <filesystem>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include "argument_order.h"
#include "commands.h"
#include "isocorr/eval/ground_truth.h"
#include "isocorr/eval/metrics.h"
#include "isocorr/output/map_files.h"
#include "isocorr/output/precise_map_files.h"
#include "isocorr/util/error.h"
#include "isocorr/geodesic/geodesic_diameter.h"
#include "mesh_files.h"

namespace isocorr::cli {
namespace {

constexpr const char* kUsage = "isocorr eval SOURCE TARGET MAP";

struct EvalArguments {
  std::string source, target, map, dataset, gt_kind, errors_out;
  int max_points = 2000;
  bool json = false;
  bool precise = false;  // MAP is a precise map (match --precise-out)
};

// A precise map's nearest corners: the vertex map it refines.
std::vector<int> nearest_corners(const TriangleMesh& target, const PreciseMap& precise) {
  std::vector<int> corners(precise.size());
  for (size_t v = 0; v < precise.size(); ++v) {
    if (precise[v].face < 0) throw InputError("the precise map leaves source vertex " + std::to_string(v) + " unmatched");
    corners[v] = nearest_corner(target, precise[v]);
  }
  return corners;
}

// One line per scored point: source vertex, error / diameter, 1 if nearer its mirror image.
void write_point_errors(const std::string& path, const GroundTruthScore& score) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) throw InputError("cannot write " + path);
  std::fprintf(file, "# source_vertex error_over_diameter nearer_mirror\n");
  for (size_t i = 0; i < score.point_errors.size(); ++i)
    std::fprintf(file, "%d %.6f %d\n", score.point_sources[i], score.point_errors[i],
                 static_cast<int>(score.point_nearer_mirror[i]));
  if (std::fclose(file) != 0) throw InputError("cannot write " + path);
}

int run_eval(const EvalArguments& args) {
  try {
    check_meshes_before_map(kUsage, args.source, args.map);
    // Mesh paths are taken as given when absolute or when there is no dataset folder.
    const std::filesystem::path dataset = args.dataset.empty() ? "." : args.dataset;
    BenchmarkPair pair{(dataset / args.source).lexically_normal().string(),
                       (dataset / args.target).lexically_normal().string(), args.gt_kind, ""};
    if (pair.gt_kind.empty()) {  // look the pair up in the dataset's list
      if (args.dataset.empty()) throw InputError("give --gt-kind, or --dataset with a pairs.tsv that lists the pair");
      for (auto listed : read_pairs_tsv(args.dataset)) {
        listed.source_path = std::filesystem::path(listed.source_path).lexically_normal().string();
        listed.target_path = std::filesystem::path(listed.target_path).lexically_normal().string();
        if (listed.source_path == pair.source_path && listed.target_path == pair.target_path) pair = listed;
      }
      if (pair.gt_kind.empty())
        throw InputError("pair not in " + args.dataset + "/pairs.tsv; give --gt-kind");
    }
    const LoadedMesh source = load_mesh_file("source", pair.source_path);
    const LoadedMesh target = load_mesh_file("target", pair.target_path);
    PreciseMap precise;
    std::vector<int> forward;
    if (args.precise) {
      precise = read_precise_map(args.map);
      check_precise_map_fits(precise, source.mesh.num_vertices(), target.mesh.num_faces());
      forward = nearest_corners(target.mesh, precise);
    } else {
      forward = read_map(args.map);
    }
    check_map_fits(forward, source.mesh.num_vertices(), target.mesh.num_vertices());
    const GroundTruth truth =
        load_ground_truth(dataset.string(), pair, source.mesh.num_vertices(), target.mesh.num_vertices());
    const MeshTopology topology(target.mesh);
    const FastMarching geodesics(target.mesh, topology);
    const double diameter = estimate_geodesic_diameter(geodesics);
    EvaluationOptions options;
    options.max_points = args.max_points;
    if (args.precise) options.precise = &precise;
    const GroundTruthScore score = score_against_ground_truth(target.mesh, geodesics, diameter, forward, truth, options);
    if (!args.errors_out.empty()) write_point_errors(args.errors_out, score);
    const std::vector<int> seed_counts = {10, 20, 50, 100, 200, 500};
    const std::vector<double> covered = coverage(target.mesh, geodesics, forward, seed_counts);
    if (args.json) {
      nlohmann::json out = {{"evaluated", score.evaluated},     {"d_grd", score.mean_error},
                            {"d_grd_max", score.max_error},     {"kim_auc", score.kim_auc},
                            {"kim_mean", score.mean_kim_error}, {"mirrored_fraction", score.mirrored_fraction},
                            {"far_fraction", score.far_fraction}, {"flip_free", score.flip_free},
                            {"flip_rule", score.flip_rule},     {"ground_truth", truth.description},
                            {"coverage_seeds", seed_counts},    {"coverage", covered}};
      std::printf("%s\n", out.dump(2).c_str());
    } else {
      std::printf("ground truth   %s\nevaluated      %d points\nD_grd          %.4f\nd_grd-dagger   %.4f\n"
                  "Kim AUC        %.4f\nmirrored       %.3f\nflip-free      %s (%s)\n",
                  truth.description.c_str(), score.evaluated, score.mean_error, score.max_error, score.kim_auc,
                  score.mirrored_fraction, score.flip_free ? "yes" : "no", score.flip_rule.c_str());
      std::printf("coverage       ");
      for (size_t i = 0; i < seed_counts.size(); ++i) std::printf("%s%d cells %.3f", i ? ", " : "", seed_counts[i], covered[i]);
      std::printf(" (SHREC'20: share of target area whose Voronoi cell holds an image)\n");
    }
    return kExitOk;
  } catch (const InputError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    spdlog::error("eval failed: {}", e.what());
    return kExitFailure;
  }
}

}  // namespace

void register_eval_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<EvalArguments>();
  CLI::App* cmd = app.add_subcommand("eval", "score a map against a benchmark dataset's ground truth");
  cmd->add_option("source", args->source, "source mesh (relative paths: to the dataset folder if given)")->required();
  cmd->add_option("target", args->target, "target mesh (relative paths: to the dataset folder if given)")->required();
  // Not checked for existence here: the map-first order would be refused as a missing map
  // before run_eval could name the order.
  cmd->add_option("map", args->map, "source-to-target map written by `isocorr match`")->required();
  // The meshes were once --source and --target flags: those say the order instead of
  // leaving CLI11 to report a missing positional.
  for (const char* old_flag : {"--source", "--target"})
    cmd->add_option_function<std::string>(old_flag, [old_flag](const std::string&) {
         throw CLI::ValidationError(std::string(old_flag) + " is gone, the meshes are positional: `" + kUsage + "`");
       })->group("");
  cmd->add_option("--dataset", args->dataset,
                  "dataset folder: relative mesh and ground-truth paths start there, and its pairs.tsv gives the "
                  "ground-truth kind when --gt-kind is not given (e.g. ../shared/data/tosca_hires)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--gt-kind", args->gt_kind,
                  "ground-truth kind: identity, vts, prefix6890, ref_to_null, sparse_vts or index_map:FILE "
                  "(default: looked up in the dataset's pairs.tsv)");
  cmd->add_option("--max-points", args->max_points, "ground-truth points scored (0 = all)")->capture_default_str();
  cmd->add_flag("--json", args->json, "print JSON");
  cmd->add_flag("--precise", args->precise,
                "MAP is a precise map (match --precise-out): errors are measured from each vertex's point");
  cmd->add_option("--errors-out", args->errors_out,
                  "write each scored point's source vertex, error / diameter and mirror flag, one per line");
  cmd->callback([args, &exit_code] { exit_code = run_eval(*args); });
}

}  // namespace isocorr::cli
