// The subcommands that call isocorr-server, one per API call, each in its own
// <name>_command.cpp: upload, submit, status, watch, wait, cancel, download, list, delete,
// health.
#pragma once

#include "commands.h"
#include "remote/connection.h"

namespace isocorr::cli {

// Registers them on `app` and returns the runner `isocorr match --server` uses.
RemoteMatchRunner register_remote_commands(CLI::App& app, ConnectionOptions& connection, int& exit_code);

// `isocorr match ... --server`: upload, submit, follow, download (remote_match.cpp).
int run_remote_match(const ConnectionOptions& connection, const MatchJobFiles& files);

}  // namespace isocorr::cli
