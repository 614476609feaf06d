// `isocorr transfer SOURCE TARGET MAP --attribute FILE -o OUT`: carries per-vertex
// attributes of the target onto the source through a map (a vertex map, or with --precise
// a precise map, whose points interpolate them). With --uv instead of --attribute, the
// source gets the UVs and materials of a textured OBJ target.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "argument_order.h"
#include "commands.h"
#include "isocorr/output/attribute_files.h"
#include "isocorr/output/map_files.h"
#include "isocorr/mesh/textured_mesh.h"
#include "isocorr/output/precise_map_files.h"
#include "isocorr/transfer/uv_transfer.h"
#include "isocorr/util/error.h"
#include "mesh_files.h"

namespace isocorr::cli {
namespace {

constexpr const char* kUsage = "isocorr transfer SOURCE TARGET MAP (--attribute FILE | --uv) -o OUT";

struct TransferArguments {
  std::string source, target, map, attribute, output;
  std::vector<std::string> properties = kPlyColourProperties;  // of a .ply attribute file
  bool precise = false;  // MAP is a precise map
  bool labels = false;   // integer labels: the majority, never interpolated
  bool uv = false;       // the target's texture coordinates and materials, onto an OBJ
};

// The map as points on the target: read as given with --precise, made from a vertex map
// otherwise.
PreciseMap points_on_target(const TransferArguments& args, const TriangleMesh& source, const TriangleMesh& target) {
  if (args.precise) {
    PreciseMap precise = read_precise_map(args.map);
    check_precise_map_fits(precise, source.num_vertices(), target.num_faces());
    return precise;
  }
  const std::vector<int> map = read_map(args.map);
  check_map_fits(map, source.num_vertices(), target.num_vertices(), true);
  return precise_map(source, target, map);
}

// The source as an OBJ with the target's UVs and materials, and its own normals.
void transfer_texture(const TransferArguments& args) {
  if (!args.output.ends_with(".obj")) throw InputError("--uv writes an OBJ file: name the output *.obj");
  TexturedMesh source = load_textured_mesh(args.source);
  const TexturedMesh target = load_textured_mesh(args.target);
  const CornerAttributes normals = source.corners;
  source.corners = transfer_uvs(source.mesh, target, points_on_target(args, source.mesh, target.mesh));
  source.corners.normals = normals.normals;
  source.corners.face_normals = normals.face_normals;
  write_textured_obj(args.output, source);
  spdlog::info("{} texture coordinates of {} carried onto the {} source faces; written to {}{}",
               target.corners.uvs.size(), args.target, source.mesh.num_faces(), args.output,
               target.corners.material_library.empty() ? ""
                                                       : " (materials from " + target.corners.material_library + ")");
}

// The attributes or labels pulled onto the source, written to args.output.
void transfer(const TransferArguments& args, const TriangleMesh& source, const TriangleMesh& target,
              const VertexTable& attributes) {
  if (attributes.rows != target.num_vertices())
    throw InputError(args.attribute + ": " + std::to_string(attributes.rows) + " rows for a target of " +
                     std::to_string(target.num_vertices()) + " vertices");
  PreciseMap precise;
  std::vector<int> map;
  if (args.precise) {
    precise = points_on_target(args, source, target);
  } else {
    map = read_map(args.map);
    check_map_fits(map, source.num_vertices(), target.num_vertices(), true);
  }
  if (args.labels) {
    const std::vector<int64_t> target_labels = labels_of(attributes, args.attribute);
    write_labels(args.output, args.precise ? pull_labels(target, target_labels, precise) : pull_labels(target_labels, map));
    return;
  }
  const VertexTable pulled = args.precise ? pull_values(target, attributes, precise) : pull_values(attributes, map);
  if (args.output.ends_with(".ply")) write_coloured_ply(args.output, source, pulled);
  else write_vertex_table(args.output, pulled);
}

int run_transfer(const TransferArguments& args) {
  try {
    check_meshes_before_map(kUsage, args.source, args.map);
    if (args.uv == !args.attribute.empty()) throw InputError("give either --attribute FILE or --uv: `" + std::string(kUsage) + "`");
    if (args.uv) {
      transfer_texture(args);
      return kExitOk;
    }
    const LoadedMesh source = load_mesh_file("source", args.source);
    const LoadedMesh target = load_mesh_file("target", args.target);
    const VertexTable attributes = read_vertex_table(args.attribute, args.properties);
    transfer(args, source.mesh, target.mesh, attributes);
    spdlog::info("{} column{} of {} carried onto the {} source vertices; written to {}", attributes.columns,
                 attributes.columns == 1 ? "" : "s", args.attribute, source.mesh.num_vertices(), args.output);
    return kExitOk;
  } catch (const InputError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    spdlog::error("transfer failed: {}", e.what());
    return kExitFailure;
  }
}

}  // namespace

void register_transfer_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<TransferArguments>();
  CLI::App* cmd = app.add_subcommand("transfer", "carry per-vertex attributes of TARGET onto SOURCE through a map");
  cmd->add_option("source", args->source, "source mesh (OFF, OBJ or PLY)")->required()->check(CLI::ExistingFile);
  cmd->add_option("target", args->target, "target mesh (OFF, OBJ or PLY)")->required()->check(CLI::ExistingFile);
  cmd->add_option("map", args->map, "source-to-target map written by `isocorr match`")->required();
  cmd->add_option("--attribute", args->attribute,
                  "the target's attributes, one row per vertex: text or CSV (a header line is skipped), .npy "
                  "(N,) or (N, M), or a .ply mesh's vertex properties (--properties)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--properties", args->properties,
                  "the vertex properties of a .ply attribute file, comma-separated (e.g. a skin weight)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("-o,--output", args->output,
                  "the source's attributes: .npy (float64), .csv, text, or .ply (the source mesh coloured by three "
                  "columns, 0-1 or 0-255); with --uv the textured source, .obj")
      ->required();
  cmd->add_flag("--precise", args->precise,
                "MAP is a precise map (match --precise-out): attributes are interpolated at each vertex's point");
  cmd->add_flag("--uv", args->uv,
                "instead of --attribute: give the source the texture coordinates and materials of TARGET (an OBJ "
                "with vt); OUT is an OBJ naming the target's material library, so keep it beside the .mtl");
  cmd->add_flag("--labels", args->labels,
                "the attribute is one column of integer labels: each vertex takes the label of most weight, "
                "never a blend (unmatched: -1)");
  cmd->callback([args, &exit_code] { exit_code = run_transfer(*args); });
}

}  // namespace isocorr::cli
