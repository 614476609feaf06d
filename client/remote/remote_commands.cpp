#include "remote/remote_commands.h"

#include "remote/remote_subcommand.h"

namespace isocorr::cli {

RemoteMatchRunner register_remote_commands(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  // In this order in --help: files up, a job in, following it, its result, the listings.
  register_upload_command(app, options, exit_code);
  register_submit_command(app, options, exit_code);
  register_status_command(app, options, exit_code);
  register_watch_command(app, options, exit_code);
  register_wait_command(app, options, exit_code);
  register_cancel_command(app, options, exit_code);
  register_download_command(app, options, exit_code);
  register_list_command(app, options, exit_code);
  register_delete_command(app, options, exit_code);
  register_health_command(app, options, exit_code);
  return [&options](const MatchJobFiles& files) -> std::optional<int> {
    if (options.server.empty()) return std::nullopt;
    return run_remote_match(options, files);
  };
}

}  // namespace isocorr::cli
