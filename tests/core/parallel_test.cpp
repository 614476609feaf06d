// The parallel loops: every index once, and the workers shared out among the last bodies.
#include "isocorr/util/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace isocorr {
namespace {

// The workers each index of [0, count) was given by `run` (a loop handed the body), each
// index checked to be called once.
template <class Run>
std::vector<int> workers_given(int count, const Run& run) {
  std::vector<int> workers(count, 0);
  std::vector<std::atomic<int>> calls(count);
  run([&](int i, int w) {
    workers[i] = w;
    ++calls[i];
  });
  for (int i = 0; i < count; ++i) EXPECT_EQ(calls[i].load(), 1) << "index " << i;
  return workers;
}

std::vector<int> workers_per_index(int count, int threads) {
  return workers_given(count, [&](const auto& body) { parallel_for_sharing(count, threads, body); });
}

TEST(ParallelForSharing, FullRoundsTakeOneWorkerEachAndTheLastBodiesShareTheRest) {
  EXPECT_EQ(workers_per_index(3, 2), (std::vector<int>{1, 1, 2}));
  EXPECT_EQ(workers_per_index(4, 2), (std::vector<int>{1, 1, 1, 1}));
  EXPECT_EQ(workers_per_index(5, 4), (std::vector<int>{1, 1, 1, 1, 4}));
  EXPECT_EQ(workers_per_index(2, 5), (std::vector<int>{3, 2}));
  EXPECT_EQ(workers_per_index(3, 1), (std::vector<int>{1, 1, 1}));
  EXPECT_TRUE(workers_per_index(0, 2).empty());
}

std::vector<int> workers_costly_first(const std::vector<bool>& costly, int threads) {
  return workers_given(static_cast<int>(costly.size()),
                       [&](const auto& body) { parallel_for_costly_first(costly, threads, body); });
}

TEST(ParallelForCostlyFirst, CheapBodiesJoinTheLastWholeRoundOfCostlyOnes) {
  // Two costly bodies fill a round of two workers: the cheap ones run beside it, one worker each.
  EXPECT_EQ(workers_costly_first({true, false, true, false}, 2), (std::vector<int>{1, 1, 1, 1}));
  EXPECT_EQ(workers_costly_first({true, true, true, true, false}, 2), (std::vector<int>{1, 1, 1, 1, 1}));
}

TEST(ParallelForCostlyFirst, ALoneLastCostlyBodyTakesEveryWorkerBeforeTheCheapOnes) {
  // Three costly bodies on two workers: the third has both, and then so has the cheap one.
  EXPECT_EQ(workers_costly_first({true, true, false, true}, 2), (std::vector<int>{1, 1, 2, 2}));
  EXPECT_EQ(workers_costly_first({false, false, true, false}, 4), (std::vector<int>{2, 1, 4, 1}));
}

TEST(ParallelForCostlyFirst, BodiesAllAlikeShareTheWorkersAsParallelForSharing) {
  EXPECT_EQ(workers_costly_first({true, true, true}, 2), workers_per_index(3, 2));
  EXPECT_EQ(workers_costly_first({false, false, false}, 2), workers_per_index(3, 2));
  EXPECT_EQ(workers_costly_first({true, false, true, false}, 1), (std::vector<int>{1, 1, 1, 1}));
  EXPECT_TRUE(workers_costly_first({}, 2).empty());
}

TEST(ParallelForCostlyFirst, OnOneWorkerTheCostlyBodiesRunFirst) {
  std::vector<int> order;
  parallel_for_costly_first({false, true, false, true, false}, 1, [&](int i, int) { order.push_back(i); });
  EXPECT_EQ(order, (std::vector<int>{1, 3, 0, 2, 4}));
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
