// `isocorr match SOURCE TARGET -o MAP`: the engine in-process, the embedded default.
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "isocorr/output/colour_transfer.h"
#include "isocorr/output/map_files.h"
#include "isocorr/output/match_report.h"
#include "isocorr/pipeline/run_match.h"
#include "mesh_files.h"
#include "precise_outputs.h"
#include "progress_printer.h"
#include "settings_flags.h"
#include "verdict_line.h"

namespace isocorr::cli {
namespace {

// The first Ctrl-C cancels the match at its next safe point (within a second); a second one
// ends the process at once.
std::atomic<bool> g_interrupted{false};
void on_interrupt(int) {
  if (g_interrupted.exchange(true)) std::_Exit(130);
}

// Every file the match will write goes into an existing directory: said before the match
// runs, not after it.
void check_output_directories(const MatchJobFiles& args) {
  const std::pair<const char*, const std::string*> outputs[] = {
      {"map", &args.output}, {"reverse map", &args.reverse_output}, {"report", &args.report},
      {"coloured meshes", &args.colour_ply}, {"precise map", &args.precise_output},
      {"reverse precise map", &args.reverse_precise_output}};
  for (const auto& [what, file] : outputs) {
    if (file->empty()) continue;
    std::filesystem::path directory = std::filesystem::path(*file).parent_path();
    if (directory.empty()) directory = ".";
    std::error_code error;
    if (!std::filesystem::is_directory(directory, error))
      throw InputError(std::string("cannot write the ") + what + " to '" + *file + "': the directory '" +
                       directory.string() + "' does not exist");
  }
}

int match_locally(const MatchJobFiles& args) {
  const auto start = std::chrono::steady_clock::now();
  try {
    ReportInput source_input{args.source, ""}, target_input{args.target, ""};
    const LoadedMesh source = load_mesh_file("source", args.source, &source_input.sha256);
    const LoadedMesh target = load_mesh_file("target", args.target, &target_input.sha256);
    // The match would refuse an unusable mesh without saying which of the two it was. Cleaning
    // here and again in the match costs 45 ms at 52K vertices (docs/decisions.md).
    check_matchable_file("source", args.source, source, args.settings.preprocess.cleaning);
    check_matchable_file("target", args.target, target, args.settings.preprocess.cleaning);
    check_landmarks_fit(args.landmarks_file, args.settings.landmarks, source.mesh.num_vertices(),
                        target.mesh.num_vertices());
    spdlog::info("source {}: {} vertices, {} faces ({})", args.source, source.mesh.num_vertices(),
                 source.mesh.num_faces(), source.format);
    spdlog::info("target {}: {} vertices, {} faces ({})", args.target, target.mesh.num_vertices(),
                 target.mesh.num_faces(), target.format);
    for (const auto& note : source.notes) spdlog::warn("source: {}", note);
    for (const auto& note : target.notes) spdlog::warn("target: {}", note);

    std::signal(SIGINT, on_interrupt);
    JobControl control;
    ProgressPrinter printer;
    control.on_progress = [&](const Progress& p) { printer(p); };
    control.cancel_requested = &g_interrupted;
    const MatchResult result = match_meshes(source.mesh, target.mesh, args.settings, control);
    for (const auto& warning : result.messages.warnings) spdlog::warn("{}", warning);
    for (const auto& note : result.messages.notes) spdlog::info("{}", note);

    const MatchOutput& out = result.output;
    write_map(args.output, out.forward);
    if (!args.reverse_output.empty()) write_map(args.reverse_output, out.reverse);
    if (!args.report.empty()) {
      std::ofstream report(args.report);
      report << report_with_inputs(out.report_json, source_input, target_input) << '\n';
      if (!report) throw InputError("cannot write report '" + args.report + "'");
    }
    if (!args.colour_ply.empty()) write_colour_ply_pair(args.colour_ply, source.mesh, target.mesh, out.reverse);
    write_precise_outputs(args, out.forward_precise, out.reverse_precise);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // The report's numbers: its "chosen" tracked map and its final orientation.
    const TrackingDiagnostics& tracking = result.diagnostics.tracking;
    spdlog::info("matched {} -> {} vertices in {:.2f} s: D_iso {:.4f}, orientation {:.2f}, tracked {} of {} level-0 "
                 "maps, chose tracked map {} (level-0 rank {}); map written to {}",
                 out.forward.size(), out.reverse.size(), seconds, result.quality.diso, result.quality.orientation,
                 tracking.maps.size(), result.diagnostics.level0.maps.size(), tracking.chosen,
                 tracking.maps[tracking.chosen].level0_rank, args.output);
    if (args.settings.method != MatchMethod::kFull)
      spdlog::info("part matching: {:.1f}% of the target's area matched (reverse map -1 elsewhere), part scale {:.3f}",
                   100 * result.quality.target_matched_share, result.quality.part_scale);
    log_verdict(result.verdict.status(), result.verdict.reasons);
    return kExitOk;
  } catch (const InputError& e) {
    spdlog::error("{}", with_flag_names(e.what()));  // the engine names settings as the API does
    return kExitBadInput;
  } catch (const Cancelled&) {
    spdlog::error("interrupted: no map written");
    return kExitCancelled;
  } catch (const std::exception& e) {
    spdlog::error("match failed: {}", e.what());
    return kExitFailure;
  }
}

}  // namespace

void register_match_command(CLI::App& app, int& exit_code, RemoteMatchRunner remote) {
  auto args = std::make_shared<MatchJobFiles>();
  CLI::App* cmd = app.add_subcommand("match", "match SOURCE to TARGET and write the dense map");
  cmd->add_option("source", args->source, "source mesh (OFF, OBJ or PLY)")->required()->check(CLI::ExistingFile);
  cmd->add_option("target", args->target, "target mesh (OFF, OBJ or PLY)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output,
                  "map file: one 0-based target vertex per source vertex, one per line (binary if it ends in .bin, NumPy if .npy)")
      ->required();
  cmd->add_option("--reverse-out", args->reverse_output, "also write the target-to-source map");
  cmd->add_option("--report", args->report, "write a JSON report (timings, candidates, tracked maps, D_iso)");
  cmd->add_option("--colour-ply", args->colour_ply,
                  "write PREFIXsource.ply and PREFIXtarget.ply, the target coloured through the map");
  cmd->add_option("--precise-out", args->precise_output,
                  "also write the precise map: per source vertex a target face and its corners' weights "
                  "('face w0 w1 w2' lines; NumPy (N, 4) if .npy)");
  cmd->add_option("--reverse-precise-out", args->reverse_precise_output, "the same for the reverse map");
  add_match_settings_flags(*cmd, args->settings, args->landmarks_file);
  cmd->callback([args, remote, &exit_code] {
    try {
      check_output_directories(*args);
    } catch (const InputError& e) {
      spdlog::error("{}", e.what());
      exit_code = kExitBadInput;
      return;
    }
    if (remote)
      if (const std::optional<int> code = remote(*args)) {
        exit_code = *code;
        return;
      }
    exit_code = match_locally(*args);
  });
}

}  // namespace isocorr::cli
