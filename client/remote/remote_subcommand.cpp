#include "remote/remote_subcommand.h"

#include <cstdio>
#include <memory>

#include <CLI/CLI.hpp>

#include "remote/rpc_error.h"

namespace isocorr::cli {

CLI::App* add_remote_command(CLI::App& app, const char* name, const char* help, ConnectionOptions& options,
                             int& exit_code, std::function<int(Connection&, bool json)> run) {
  CLI::App* cmd = app.add_subcommand(name, help);
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "print the API's JSON instead of text");
  cmd->footer("Server connection (before or after the subcommand): --server HOST:PORT (default 127.0.0.1:50051), "
              "--token-file FILE, --tls, --tls-ca PEM, --timeout S; see isocorr --help.");
  cmd->callback([&options, &exit_code, json, run] {
    exit_code = run_remote_command(*json, [&] {
      Connection connection(options);
      return run(connection, *json);
    });
  });
  return cmd;
}

void print_line(const std::string& text) { std::printf("%s\n", text.c_str()); }

}  // namespace isocorr::cli
