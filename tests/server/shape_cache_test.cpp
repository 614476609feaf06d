// The server's cache of preprocessed meshes: one build per key however many jobs ask at
// once, LRU eviction by bytes, and failed builds forgotten.
#include "jobs/shape_cache.h"

#include <atomic>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"

namespace isocorr::server {
namespace {

ShapeCache::ShapePtr small_shape() {
  return PreprocessedShape::build(limbed_blob(2), PreprocessOptions(), JobControl().with_threads(1));
}

TEST(ShapeCache, ConcurrentRequestsForOneKeyBuildOnce) {
  ShapeCache cache(int64_t{1} << 30);
  std::atomic<int> builds{0};
  std::vector<ShapeCache::ShapePtr> results(4);
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i)
    threads.emplace_back([&, i] {
      results[i] = cache.get_or_build("mesh|opts", [&] {
        ++builds;
        return small_shape();
      });
    });
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(builds.load(), 1);
  for (const auto& result : results) EXPECT_EQ(result, results[0]);
  EXPECT_EQ(cache.state_of_mesh("mesh"), ShapeCache::MeshState::kReady);
  EXPECT_EQ(cache.stats().misses, 1);
  EXPECT_EQ(cache.stats().hits, 3);
}

TEST(ShapeCache, EvictsLeastRecentlyUsedBeyondCapacity) {
  const ShapeCache::ShapePtr shape = small_shape();
  const auto bytes = static_cast<int64_t>(shape->memory_bytes());
  ShapeCache cache(2 * bytes + bytes / 2);  // room for two
  auto same = [&] { return shape; };
  cache.get_or_build("a|o", same);
  cache.get_or_build("b|o", same);
  cache.get_or_build("a|o", same);  // a is now the most recent
  cache.get_or_build("c|o", same);  // evicts b
  EXPECT_EQ(cache.state_of_mesh("a"), ShapeCache::MeshState::kReady);
  EXPECT_EQ(cache.state_of_mesh("b"), ShapeCache::MeshState::kAbsent);
  EXPECT_EQ(cache.state_of_mesh("c"), ShapeCache::MeshState::kReady);
  EXPECT_EQ(cache.stats().bytes, 2 * bytes);
  EXPECT_EQ(cache.stats().evictions, 1);
}

TEST(ShapeCache, FailedBuildIsForgottenAndRetried) {
  ShapeCache cache(int64_t{1} << 30);
  EXPECT_THROW(cache.get_or_build("k|o", []() -> ShapeCache::ShapePtr { throw Cancelled(); }), Cancelled);
  EXPECT_EQ(cache.state_of_mesh("k"), ShapeCache::MeshState::kAbsent);
  EXPECT_NE(cache.get_or_build("k|o", small_shape), nullptr);
}

}  // namespace
}  // namespace isocorr::server
