// The remote subcommands, each registered from its own file: all listed after the local
// ones, each with --json and the connection flags in its help. No server is needed.
#include <string>

#include <gtest/gtest.h>

#include "../shell_run.h"

namespace {

using isocorr::testing::run_shell;
using isocorr::testing::ShellRun;

const char* const kRemoteCommands[] = {"upload", "submit", "status", "watch", "wait",
                                       "cancel", "download", "list", "delete", "health"};

TEST(RemoteCommands, AllListedInOrderAfterTheLocalOnes) {
  const ShellRun help = run_shell(std::string(ISOCORR_CLI_PATH) + " --help");
  ASSERT_EQ(help.exit_code, 0) << help.output;
  size_t previous = help.output.find("  cut");
  ASSERT_NE(previous, std::string::npos) << help.output;
  for (const char* name : kRemoteCommands) {
    const size_t at = help.output.find("  " + std::string(name) + " ");
    ASSERT_NE(at, std::string::npos) << name << "\n" << help.output;
    EXPECT_GT(at, previous) << name << "\n" << help.output;
    previous = at;
  }
}

TEST(RemoteCommands, EachTakesJsonAndNamesTheConnectionFlags) {
  for (const char* name : kRemoteCommands) {
    const ShellRun help = run_shell(std::string(ISOCORR_CLI_PATH) + " " + name + " --help");
    EXPECT_EQ(help.exit_code, 0) << name << "\n" << help.output;
    EXPECT_NE(help.output.find("--json"), std::string::npos) << name << "\n" << help.output;
    EXPECT_NE(help.output.find("--server HOST:PORT"), std::string::npos) << name << "\n" << help.output;
  }
}

}  // namespace
