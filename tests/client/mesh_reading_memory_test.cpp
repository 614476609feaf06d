// The memory `isocorr` takes to read and clean a hostile mesh file, measured on the real binary
// as the kernel counts it (peak resident set): bounded by kReadingPeakPerFileByte times the
// file's size, where a polygon of millions of corners over four vertices once took 52 times.
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "isocorr/mesh/mesh_io.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;

struct PeakRun {
  int exit_code = -1;
  long peak_bytes = 0;
};

// Runs the CLI on `mesh` against itself, output discarded, and returns its peak resident set.
PeakRun run_cli_on(const fs::path& mesh) {
  const std::string cli = ISOCORR_CLI_PATH, path = mesh.string(), map = mesh.string() + ".map";
  std::vector<char*> argv = {const_cast<char*>(cli.c_str()), const_cast<char*>("match"),
                             const_cast<char*>(path.c_str()), const_cast<char*>(path.c_str()),
                             const_cast<char*>("-o"), const_cast<char*>(map.c_str()), nullptr};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  PeakRun run;
  if (posix_spawn(&pid, cli.c_str(), &actions, nullptr, argv.data(), environ) != 0) return run;
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  rusage usage{};
  if (wait4(pid, &status, 0, &usage) != pid) return run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.peak_bytes = usage.ru_maxrss * 1024L;
  return run;
}

class MeshReadingMemory : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("isocorr_memory_test_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(MeshReadingMemory, HostileFilesStayWithinTheStatedMultipleOfTheirSize) {
  // What the process takes before any mesh: a tiny file the reader refuses at once.
  const fs::path tiny = dir_ / "tiny.off";
  std::ofstream(tiny) << "OFF\n0 0 0\n";
  const PeakRun baseline = run_cli_on(tiny);
  ASSERT_EQ(baseline.exit_code, 2);

  // 200 000 vertices and as many triangles as the readers allow, as short as text can write
  // them: one polygon over nine vertices, repeated.
  const fs::path dense = dir_ / "dense.obj";
  {
    std::ofstream out(dense);
    for (int i = 0; i < 200'000; ++i) out << "v " << i % 97 << ' ' << (i / 97) % 89 << ' ' << i / 8633 << '\n';
    for (int p = 0; p < 16 * 200'000 / 7 - 200; ++p) out << "f 1 2 3 4 5 6 7 8 9\n";
  }
  // One polygon of 25 M corners over four vertices.
  const fs::path polygon = dir_ / "polygon.obj";
  {
    std::ofstream out(polygon);
    out << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf";
    for (int k = 0; k < 6'250'000; ++k) out << " 1 2 3 4";
    out << '\n';
  }
  for (const fs::path& file : {dense, polygon}) {
    const PeakRun run = run_cli_on(file);
    EXPECT_EQ(run.exit_code, 2) << file;  // neither can be matched
    const long size = static_cast<long>(fs::file_size(file));
    EXPECT_LE(run.peak_bytes - baseline.peak_bytes, isocorr::kReadingPeakPerFileByte * size)
        << file << ": " << size << " bytes took " << run.peak_bytes << " (the process alone "
        << baseline.peak_bytes << ")";
  }
}

}  // namespace
