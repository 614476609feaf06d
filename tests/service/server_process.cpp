#include "server_process.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace isocorr::testing {
namespace fs = std::filesystem;

std::string slurp_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

CommandRun run_command(const std::string& command) {
  static int counter = 0;
  const fs::path err = fs::temp_directory_path() / ("isocorr_cmd_" + std::to_string(getpid()) + "_" +
                                                   std::to_string(++counter) + ".err");
  CommandRun result;
  FILE* pipe = popen((command + " 2>" + err.string()).c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  while (fgets(buffer, sizeof buffer, pipe)) result.out += buffer;
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.err = slurp_file(err);
  fs::remove(err);
  return result;
}

std::string python_grpc_command(const std::string& script, const std::string& address, const fs::path& work) {
  std::string command = std::string("timeout --kill-after=5 300 /usr/bin/python3 ") + ISOCORR_SERVICE_TEST_DIR + "/" +
                        script + " --server " + address + " --work " + work.string();
  for (const char* dir : {ISOCORR_PROTO_DIR, ISOCORR_GRPC_PROTO_DIR, ISOCORR_GOOGLEAPIS_PROTO_DIR})
    command += std::string(" --proto-path ") + dir;
  return command;
}

pid_t spawn_command(const std::string& command, const fs::path& log) {
  const std::string line = "exec " + command + " >" + log.string() + " 2>&1";
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

int wait_for_exit(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

ServerProcess::ServerProcess(fs::path data_dir, std::vector<std::string> extra)
    : data_dir_(std::move(data_dir)), log_(data_dir_.string() + ".log") {
  fs::create_directories(data_dir_);
  const fs::path port_file = data_dir_.string() + ".port";
  fs::remove(port_file);
  std::vector<std::string> args = {ISOCORR_SERVER_PATH, "--data-dir", data_dir_.string(), "--port-file",
                                   port_file.string(), "--log-level", "debug"};
  if (std::find(extra.begin(), extra.end(), "--listen") == extra.end())
    args.insert(args.end(), {"--listen", "127.0.0.1:0"});
#ifdef ISOCORR_SANITIZED
  // A server stops at the grace period whatever its workers do; instrumented builds run 5 to
  // 20 times slower, so a running job needs longer to reach the point where it stops cleanly.
  if (std::find(extra.begin(), extra.end(), "--shutdown-grace") == extra.end())
    args.insert(args.end(), {"--shutdown-grace", "120"});
#endif
  args.insert(args.end(), extra.begin(), extra.end());
  pid_ = fork();
  if (pid_ == 0) {
    FILE* log = std::fopen(log_.c_str(), "a");
    if (log) {
      dup2(fileno(log), STDOUT_FILENO);
      dup2(fileno(log), STDERR_FILENO);
    }
    std::vector<char*> argv;
    for (auto& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  // Bounded wait for the port file: the server writes it once it is listening.
  for (int i = 0; i < 600 && port_ == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (waitpid(pid_, nullptr, WNOHANG) == pid_) {
      pid_ = -1;
      throw std::runtime_error("isocorr-server exited at start:\n" + slurp_file(log_));
    }
    std::ifstream in(port_file);
    in >> port_;
  }
  if (port_ == 0) throw std::runtime_error("isocorr-server did not start in 30 s:\n" + slurp_file(log_));
}

ServerProcess::~ServerProcess() {
  if (pid_ > 0) kill_hard();
}

CommandRun ServerProcess::client(const std::string& arguments) const {
  return run_command(std::string(ISOCORR_CLI_PATH) + " --server " + address() + " " + arguments);
}

void ServerProcess::kill_hard() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGKILL);
  waitpid(pid_, nullptr, 0);
  pid_ = -1;
}

void ServerProcess::send_signal(int signal_number) const {
  if (pid_ > 0) ::kill(pid_, signal_number);
}

int ServerProcess::wait_for_exit(double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (pid_ > 0) {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    if (std::chrono::steady_clock::now() > deadline) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return -1;
}

int ServerProcess::terminate() {
  if (pid_ <= 0) return -1;
  ::kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace isocorr::testing
