// `isocorr match SOURCE TARGET -o MAP`: the engine in-process, the embedded default.
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "isocorr/matching/matcher.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/output/map_files.h"
#include "isocorr/output/match_report.h"
#include "settings_flags.h"

namespace isocorr::cli {
namespace {

std::atomic<bool> g_interrupted{false};
void on_interrupt(int) { g_interrupted = true; }

struct MatchArguments {
  std::string source, target, output, reverse_output, report;
  std::string selection = "orientation";
  MatchSettings settings;
};

// A one-line bar on a terminal, plain lines (one per stage change) otherwise.
class ProgressPrinter {
 public:
  ProgressPrinter() : terminal_(isatty(STDERR_FILENO)) {}
  void operator()(const Progress& p) {
    if (terminal_) {
      const int width = 30, filled = static_cast<int>(p.fraction * width);
      std::fprintf(stderr, "\r[%-*s] %3d%% %-18s level %d/%d", width, std::string(filled, '#').c_str(), width,
                   static_cast<int>(p.fraction * 100), p.stage.c_str(), p.level, p.levels);
      if (p.stage == "done") std::fprintf(stderr, "\n");
    } else if (p.stage != last_stage_) {
      spdlog::info("stage {} (level {}/{})", p.stage, p.level, p.levels);
    }
    last_stage_ = p.stage;
  }

 private:
  bool terminal_;
  std::string last_stage_;
};

int run_match(MatchArguments& args) {
  apply_selection(args.selection, args.settings);
  const auto start = std::chrono::steady_clock::now();
  try {
    const LoadedMesh source = load_mesh(args.source);
    const LoadedMesh target = load_mesh(args.target);
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
    for (const auto& note : result.notes) spdlog::warn("{}", note);

    write_map(args.output, result.forward);
    if (!args.reverse_output.empty()) write_map(args.reverse_output, result.reverse);
    if (!args.report.empty()) {
      std::ofstream out(args.report);
      out << match_report_json(result, args.settings) << '\n';
      if (!out) throw InputError("cannot write report '" + args.report + "'");
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    spdlog::info("matched {} -> {} vertices in {:.2f} s: D_iso {:.4f}, tracked {} of {} level-0 maps, "
                 "chose #{} (orientation {:.2f}); map written to {}",
                 result.forward.size(), result.reverse.size(), seconds, result.diso, result.tracked.size(),
                 result.level0.size(), result.tracked[result.chosen].level0_rank + 1,
                 result.tracked[result.chosen].orientation, args.output);
    return kExitOk;
  } catch (const InputError& e) {
    spdlog::error("{}", e.what());
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

void register_match_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<MatchArguments>();
  CLI::App* cmd = app.add_subcommand("match", "match SOURCE to TARGET and write the dense map");
  cmd->add_option("source", args->source, "source mesh (OFF, OBJ or PLY)")->required()->check(CLI::ExistingFile);
  cmd->add_option("target", args->target, "target mesh (OFF, OBJ or PLY)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output,
                  "map file: one 0-based target vertex per source vertex, one per line (binary if it ends in .bin)")
      ->required();
  cmd->add_option("--reverse-out", args->reverse_output, "also write the target-to-source map");
  cmd->add_option("--report", args->report, "write a JSON report (timings, candidates, tracked maps, D_iso)");
  add_match_settings_flags(*cmd, args->settings, args->selection);
  cmd->callback([args, &exit_code] { exit_code = run_match(*args); });
}

}  // namespace isocorr::cli
