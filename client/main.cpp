// `isocorr`: dense correspondence between two nearly isometric meshes.
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "commands.h"
#include "isocorr/util/huge_page_malloc.h"
#include "isocorr/version.h"
#ifdef ISOCORR_WITH_SERVICE
#include "remote/connection.h"
#include "remote/remote_commands.h"
#endif

int main(int argc, char** argv) {
  isocorr::restart_with_huge_page_malloc(argv);
  // Logs and progress on stderr, so stdout carries only results (maps, --json output).
  spdlog::set_default_logger(spdlog::stderr_color_mt("isocorr"));
  spdlog::set_pattern("[%Y-%m-%d %H:%M:%S.%e] [%^%l%$] %v");  // spdlog's default, without the logger name
  CLI::App app{"isocorr: dense isometric shape correspondence (coarse-to-fine combinatorial "
               "matching with symmetric-flip tracking)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("isocorr ") + isocorr::kVersion);
  bool verbose = false;
  app.add_flag("-v,--verbose", verbose, "log every stage");
  int exit_code = isocorr::cli::kExitOk;
#ifdef ISOCORR_WITH_SERVICE
  // Connection flags live on the top level; fallthrough lets them follow the subcommand too.
  isocorr::cli::ConnectionOptions connection;
  isocorr::cli::add_connection_flags(app, connection);
  app.fallthrough();
  // The local commands come first in --help; `match --server` runs through the remote ones,
  // registered after it.
  auto remote_match = std::make_shared<isocorr::cli::RemoteMatchRunner>();
  isocorr::cli::register_match_command(app, exit_code, [remote_match](const isocorr::cli::MatchJobFiles& files) {
    return (*remote_match)(files);
  });
#else
  isocorr::cli::register_match_command(app, exit_code);
#endif
  isocorr::cli::register_eval_command(app, exit_code);
  isocorr::cli::register_render_command(app, exit_code);
  isocorr::cli::register_cut_command(app, exit_code);
  isocorr::cli::register_transfer_command(app, exit_code);
#ifdef ISOCORR_WITH_SERVICE
  *remote_match = isocorr::cli::register_remote_commands(app, connection, exit_code);
#endif
  app.parse_complete_callback([&] {
    spdlog::set_level(verbose ? spdlog::level::debug : spdlog::level::info);
    spdlog::debug("GLIBC_TUNABLES={}", isocorr::malloc_tunables());
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : isocorr::cli::kExitBadInput;
  }
  return exit_code;
}
