// Subcommands of `isocorr`. Each registers itself on the app and runs when selected.
#pragma once

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
};

void register_match_command(CLI::App& app, int& exit_code);
void register_eval_command(CLI::App& app, int& exit_code);

}  // namespace isocorr::cli
