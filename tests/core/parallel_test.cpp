// The parallel loops: every index once, and the workers shared out among the last bodies.
#include "isocorr/util/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace isocorr {
namespace {

std::vector<int> workers_per_index(int count, int threads) {
  std::vector<int> workers(count, 0);
  std::vector<std::atomic<int>> calls(count);
  parallel_for_sharing(count, threads, [&](int i, int w) {
    workers[i] = w;
    ++calls[i];
  });
  for (int i = 0; i < count; ++i) EXPECT_EQ(calls[i].load(), 1) << "index " << i;
  return workers;
}

TEST(ParallelForSharing, FullRoundsTakeOneWorkerEachAndTheLastBodiesShareTheRest) {
  EXPECT_EQ(workers_per_index(3, 2), (std::vector<int>{1, 1, 2}));
  EXPECT_EQ(workers_per_index(4, 2), (std::vector<int>{1, 1, 1, 1}));
  EXPECT_EQ(workers_per_index(5, 4), (std::vector<int>{1, 1, 1, 1, 4}));
  EXPECT_EQ(workers_per_index(2, 5), (std::vector<int>{3, 2}));
  EXPECT_EQ(workers_per_index(3, 1), (std::vector<int>{1, 1, 1}));
  EXPECT_TRUE(workers_per_index(0, 2).empty());
}

TEST(ParallelFor, EveryIndexOnceAndTheFirstErrorRethrown) {
  std::vector<std::atomic<int>> calls(1000);
  parallel_for(1000, 2, [&](int i, int) { ++calls[i]; });
  for (const auto& c : calls) EXPECT_EQ(c.load(), 1);
  EXPECT_THROW(parallel_for(100, 2, [](int i, int) { if (i == 37) throw std::runtime_error("37"); }),
               std::runtime_error);
}

}  // namespace
}  // namespace isocorr
