// Runs the real `isocorr` binary the way a user's shell does, for the CLI tests. (The
// service tests' run_command keeps stdout and stderr apart.)
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace isocorr::testing {

struct ShellRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

inline ShellRun run_shell(const std::string& command) {
  ShellRun result;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  while (fgets(buffer, sizeof buffer, pipe)) result.output += buffer;
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

}  // namespace isocorr::testing
