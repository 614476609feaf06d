// `isocorr`: dense correspondence between two nearly isometric meshes.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"isocorr: dense isometric shape correspondence (coarse-to-fine combinatorial "
               "matching with symmetric-flip tracking)"};
  app.require_subcommand(1);
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "log every stage");
  int exit_code = isocorr::cli::kExitOk;
  isocorr::cli::register_match_command(app, exit_code);
  isocorr::cli::register_eval_command(app, exit_code);
  app.parse_complete_callback([&] { spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info); });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : isocorr::cli::kExitBadInput;
  }
  return exit_code;
}
