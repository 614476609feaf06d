// The engine reports progress from its worker threads: the printer must serialise them.
#include "progress_printer.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

namespace isocorr::cli {
namespace {

TEST(ProgressPrinter, ConcurrentReportsOfOneStageLogOneLine) {
  std::vector<std::string> lines;  // appended to without a lock of its own: the printer's must cover it
  ProgressPrinter printer([&](const std::string& line) { lines.push_back(line); }, /*terminal=*/false);
  printer({"level0", 0, 5, 0.0});
  std::atomic<bool> go{false};
  std::vector<std::thread> workers;
  for (int t = 0; t < 4; ++t)
    workers.emplace_back([&] {
      while (!go) std::this_thread::yield();
      for (int i = 0; i < 2000; ++i) printer({"tracking", 4, 5, 0.1 + 0.6 * i / 2000});
    });
  go = true;
  for (auto& w : workers) w.join();
  printer({"dense", 5, 5, 0.7});
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "stage level0 (level 0/5)");
  EXPECT_EQ(lines[1], "stage tracking (level 4/5)");
  EXPECT_EQ(lines[2], "stage dense (level 5/5)");
}

// Stages outside the coarse-to-fine hierarchy have no level to show, and the end is "done".
TEST(ProgressPrinter, LevelsOnlyWhereThereAreLevelsAndTheEndIsDone) {
  std::vector<std::string> lines;
  ProgressPrinter printer([&](const std::string& line) { lines.push_back(line); }, /*terminal=*/false);
  printer({"preprocess-source", 0, 0, 0.0});
  printer({"refine", 0, 0, 0.8});
  printer({"done", 1, 1, 1.0});
  EXPECT_EQ(lines, (std::vector<std::string>{"stage preprocess-source", "stage refine", "done"}));
}

}  // namespace
}  // namespace isocorr::cli
