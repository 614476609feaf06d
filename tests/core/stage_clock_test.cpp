// StageClock: each stage's wall and CPU time and the peak memory once it ended.
#include "isocorr/util/stage_clock.h"

#include <ctime>
#include <vector>

#include <gtest/gtest.h>

namespace isocorr {
namespace {

TEST(StageClock, RecordsEachStagesTimesAndThePeakMemorySoFar) {
  std::vector<StageTiming> timings;
  StageClock clock(timings);
  // Work until the process has spent some CPU time, however loaded the machine.
  const std::clock_t start = std::clock();
  volatile double sink = 0;
  while (std::clock() - start < CLOCKS_PER_SEC / 50) sink = sink + 1;
  clock.finish("busy");
  clock.finish("idle");
  ASSERT_EQ(timings.size(), 2u);
  EXPECT_EQ(timings[0].stage, "busy");
  EXPECT_GE(timings[0].cpu_seconds, 0.02);
  EXPECT_GE(timings[0].seconds, 0.0);
  EXPECT_GT(timings[0].peak_mb, 0.0);
  EXPECT_GE(timings[1].peak_mb, timings[0].peak_mb);  // a peak so far never falls
}

}  // namespace
}  // namespace isocorr
