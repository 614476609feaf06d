// Subcommands of `isocorr`. Each registers itself on the app and runs when selected.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "isocorr/settings/match_settings.h"
#include "landmarks_file.h"

namespace CLI {
class App;
}

namespace isocorr::cli {

// Exit codes that tell outcomes apart for scripts.
enum ExitCode : int {
  kExitOk = 0,
  kExitFailure = 1,       // the job ran and failed (or an internal error)
  kExitBadInput = 2,      // unusable input files or settings
  kExitUnavailable = 3,   // server unreachable (service mode)
  kExitCancelled = 4,
  kExitUnauthenticated = 5,  // the server wants a (valid) token: --token-file
  kExitNotDone = 6,          // `isocorr wait`: the job is still running at the timeout
};

// The files and settings of one `isocorr match`, run locally or on a server.
struct MatchJobFiles {
  std::string source, target, output, reverse_output, report;
  std::string colour_ply;  // prefix of the coloured PLY pair, empty = none
  std::string precise_output, reverse_precise_output;  // precise maps (precise_map.h), empty = none
  MatchSettings settings;
  LandmarksFile landmarks_file;  // where settings.landmarks came from, for messages
};

// Runs a match on a server when the user asked for one (`--server`), returning the exit
// code; nullopt means "run it in-process". Provided by the remote commands.
using RemoteMatchRunner = std::function<std::optional<int>(const MatchJobFiles&)>;

void register_match_command(CLI::App& app, int& exit_code, RemoteMatchRunner remote = {});
void register_eval_command(CLI::App& app, int& exit_code);
void register_render_command(CLI::App& app, int& exit_code);
void register_cut_command(CLI::App& app, int& exit_code);
void register_transfer_command(CLI::App& app, int& exit_code);

}  // namespace isocorr::cli
