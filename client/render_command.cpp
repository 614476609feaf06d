// `isocorr render SOURCE TARGET MAP -o pair.png`: a picture of a map, to see at a glance
// whether it is right, wrong or mirrored.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "argument_order.h"
#include "commands.h"
#include "isocorr/output/map_files.h"
#include "isocorr/render/pair_picture.h"
#include "isocorr/render/png_file.h"
#include "isocorr/render/view.h"
#include "isocorr/util/error.h"
#include "mesh_files.h"

namespace isocorr::cli {
namespace {

struct RenderArguments {
  std::string source, target, map, output;
  PairPictureOptions picture;
};

int run_render(const RenderArguments& args) {
  try {
    check_meshes_before_map("isocorr render SOURCE TARGET MAP", args.source, args.map);
    const std::vector<int> map = read_map(args.map);
    const LoadedMesh source = load_mesh_file("source", args.source);
    const LoadedMesh target = load_mesh_file("target", args.target);
    write_png(args.output, render_pair_picture(source.mesh, target.mesh, map, args.picture));
    spdlog::debug("wrote {} ({}x{})", args.output, args.picture.width, args.picture.height);
    return kExitOk;
  } catch (const InputError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    spdlog::error("render failed: {}", e.what());
    return kExitFailure;
  }
}

}  // namespace

void register_render_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<RenderArguments>();
  CLI::App* cmd = app.add_subcommand(
      "render", "draw source (left) and target (right) side by side as a PNG: the target coloured by position, "
                "the source through the map");
  cmd->add_option("source", args->source, "source mesh (OFF, OBJ, PLY)")->required()->check(CLI::ExistingFile);
  cmd->add_option("target", args->target, "target mesh (OFF, OBJ, PLY)")->required()->check(CLI::ExistingFile);
  cmd->add_option("map", args->map, "source-to-target map written by `isocorr match` (text, .bin or .npy)")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "PNG file to write")->required();
  cmd->add_option("--width", args->picture.width, "picture width in pixels (each mesh gets half)")
      ->check(CLI::Range(16, 8192))->capture_default_str();
  cmd->add_option("--height", args->picture.height, "picture height in pixels")
      ->check(CLI::Range(16, 8192))->capture_default_str();
  cmd->add_option("--view", args->picture.view,
                  "principal (the target along its principal axes, longest up, and the source as the map says it "
                  "is seen) or the side the eye is on in both meshes' coordinates: +z (front, +y up), -z, +x, -x, "
                  "+y (from above), -y")
      ->check(CLI::IsMember(view_names()))->capture_default_str();
  cmd->callback([args, &exit_code] { exit_code = run_render(*args); });
}

}  // namespace isocorr::cli
