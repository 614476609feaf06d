// `isocorr cut FULL -o PART.ply --index-map MAP`: a partial shape cut from a full mesh, with
// the exact correspondence back to it, to try part matching on shapes of one's own.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/output/map_files.h"
#include "isocorr/partial/partial_cut.h"
#include "isocorr/util/error.h"
#include "mesh_files.h"

namespace isocorr::cli {
namespace {

struct CutArgs {
  std::string full, output, index_map, kind = "ball";
  CutSpec spec;
};

int cut(const CutArgs& args) {
  try {
    CutSpec spec = args.spec;
    spec.kind = parse_cut_kind(args.kind);
    const LoadedMesh full = load_mesh_file("full", args.full);
    const PartialShape part = cut_partial_shape(full.mesh, spec);
    write_ply(args.output, part.mesh);
    write_map(args.index_map, part.full_vertex);
    spdlog::info("{}: {} of {} vertices; part written to {}, its vertices' numbers in {} to {}", part.description,
                 part.mesh.num_vertices(), full.mesh.num_vertices(), args.output, args.full, args.index_map);
    return kExitOk;
  } catch (const InputError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  }
}

}  // namespace

void register_cut_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<CutArgs>();
  CLI::App* cmd = app.add_subcommand("cut", "cut a partial shape from a full mesh, with its index map (test data for --partial)");
  cmd->add_option("full", args->full, "full mesh (OFF, OBJ or PLY)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "the part, as binary PLY")->required();
  cmd->add_option("--index-map", args->index_map,
                  "per part vertex, the 0-based full-mesh vertex it is (text; binary if it ends in .bin, NumPy if .npy)")
      ->required();
  cmd->add_option("--cut", args->kind, "ball (remove a geodesic ball), plane (one side of a plane) or holes")
      ->capture_default_str();
  cmd->add_option("--keep", args->spec.keep_area, "share of the area kept, in (0, 1)")->capture_default_str();
  cmd->add_option("--holes", args->spec.holes, "number of holes (--cut holes)")->capture_default_str();
  cmd->add_option("--seed", args->spec.seed, "picks the centres or the plane")->capture_default_str();
  cmd->callback([args, &exit_code] { exit_code = cut(*args); });
}

}  // namespace isocorr::cli
