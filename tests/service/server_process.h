// The real isocorr-server as a child process on a free loopback port, and the real
// isocorr client run against it. For the service integration tests.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace isocorr::testing {

struct CommandRun {
  int exit_code = -1;
  std::string out;  // stdout only (JSON with --json); stderr goes to the log
  std::string err;
};

// A file's bytes ("" when it cannot be read).
std::string slurp_file(const std::filesystem::path& path);

// Runs a shell command line; stdout and stderr are kept apart.
CommandRun run_command(const std::string& command);

// The command line that runs one of the Python gRPC scripts beside these tests against
// `address`, generating its stubs under `work`. timeout(1) bounds it at five minutes: an
// interpreter that never exits then fails its test with its output instead of stalling the
// suite.
std::string python_grpc_command(const std::string& script, const std::string& address,
                                const std::filesystem::path& work);

// Starts `command` through /bin/sh (exec'd, so the pid is the command's) with output to
// `log`; `wait_for_exit` returns its exit code.
pid_t spawn_command(const std::string& command, const std::filesystem::path& log);
int wait_for_exit(pid_t pid);

class ServerProcess {
 public:
  // Starts isocorr-server --listen 127.0.0.1:0 (unless `extra` has a --listen) --data-dir
  // `data_dir` plus `extra` flags and waits (bounded) until it has written its port.
  ServerProcess(std::filesystem::path data_dir, std::vector<std::string> extra = {});
  ~ServerProcess();

  std::string address() const { return "127.0.0.1:" + std::to_string(port_); }
  bool running() const { return pid_ > 0; }
  pid_t pid() const { return pid_; }  // for prlimit and the like
  const std::filesystem::path& log_path() const { return log_; }
  // The client with --server set, then `arguments`.
  CommandRun client(const std::string& arguments) const;

  void kill_hard();   // SIGKILL, as a crash would
  void send_signal(int signal_number) const;  // and does not wait for the server to exit
  int terminate();    // SIGTERM; returns the exit status
  // The exit status once the server has exited, or -1 if it is still running after `seconds`.
  int wait_for_exit(double seconds);

 private:
  std::filesystem::path data_dir_, log_;
  pid_t pid_ = -1;
  int port_ = 0;
};

}  // namespace isocorr::testing
