// What every remote subcommand shares: its --json flag, the connection footer of its help,
// and the way a failed call becomes a message and an exit code (run_remote_command). Each
// subcommand lives in its own <name>_command.cpp and registers itself through these.
#pragma once

#include <functional>
#include <string>

#include "remote/connection.h"

namespace CLI {
class App;
}

namespace isocorr::cli {

// Registers one subcommand with --json; `run` gets a connection opened with `options` and
// the --json flag, and returns the exit code.
CLI::App* add_remote_command(CLI::App& app, const char* name, const char* help, ConnectionOptions& options,
                             int& exit_code, std::function<int(Connection&, bool json)> run);

// One line of a command's result on stdout (logs and progress go to stderr).
void print_line(const std::string& text);

// The subcommands, one per API call; register_remote_commands registers them all.
void register_upload_command(CLI::App& app, ConnectionOptions& options, int& exit_code);
void register_submit_command(CLI::App& app, ConnectionOptions& options, int& exit_code);
void register_status_command(CLI::App& app, ConnectionOptions& options, int& exit_code);
void register_watch_command(CLI::App& app, ConnectionOptions& options, int& exit_code);
void register_wait_command(CLI::App& app, ConnectionOptions& options, int& exit_code);
void register_cancel_command(CLI::App& app, ConnectionOptions& options, int& exit_code);
void register_download_command(CLI::App& app, ConnectionOptions& options, int& exit_code);
void register_list_command(CLI::App& app, ConnectionOptions& options, int& exit_code);
void register_delete_command(CLI::App& app, ConnectionOptions& options, int& exit_code);
void register_health_command(CLI::App& app, ConnectionOptions& options, int& exit_code);

}  // namespace isocorr::cli
