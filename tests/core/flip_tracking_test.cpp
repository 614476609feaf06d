// Symmetric-flip tracking on a pair with a known answer: the true level-0 map, tracked level
// by level, lands every sample near its true image and keeps handedness; the same map with
// two samples' images exchanged (a flip) tracks to a worse distortion and orientation.
#include "isocorr/matching/flip_tracking.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <utility>

#include "creature_pair.h"

namespace isocorr {
namespace {

using testing::CreaturePair;

class FlipTracking : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { pair_ = new CreaturePair(3); }
  static void TearDownTestSuite() { delete pair_; }

  // The true level-0 map on the first m source samples, over the target's level-0 samples.
  static Level0Map true_level0_map(int m) {
    Level0Map map;
    for (int i = 0; i < m; ++i)
      map.target_of.push_back(pair_->true_target_sample(i, pair_->target->num_level0_samples()));
    return map;
  }

  static TrackedMap track(const Level0Map& map, int m) {
    const int levels = pair_->source->options().decision_level;
    TrackingOptions options;
    const TrackingPlan plan = plan_tracking(*pair_->source, m, levels, options);
    return track_map(*pair_->source, *pair_->target, plan, map, 0, options, JobControl{});
  }

  static CreaturePair* pair_;
};
CreaturePair* FlipTracking::pair_ = nullptr;

TEST_F(FlipTracking, TheTrueLevel0MapTracksToTheTrueImagesAndKeepsHandedness) {
  const int m = std::min(5, pair_->source->num_level0_samples());
  ASSERT_GE(m, 3);
  const TrackedMap tracked = track(true_level0_map(m), m);
  ASSERT_GT(static_cast<int>(tracked.pairs.size()), 4 * m);  // levels beyond 0 added samples
  int near = 0;
  for (const SamplePair& p : tracked.pairs)
    near += pair_->error(pair_->source->sample_vertex(p.source_sample), image_vertex(*pair_->target, p)) < 0.05;
  EXPECT_GE(near, 0.95 * tracked.pairs.size());
  EXPECT_GT(tracked.orientation, 0.95);
  EXPECT_LT(tracked.diso, 0.02);
}

TEST_F(FlipTracking, AFlippedLevel0MapTracksToAWorseDistortionAndOrientation) {
  const int m = std::min(5, pair_->source->num_level0_samples());
  const Level0Map truth = true_level0_map(m);
  Level0Map flipped = truth;
  std::swap(flipped.target_of[0], flipped.target_of[1]);
  const TrackedMap right = track(truth, m), wrong = track(flipped, m);
  EXPECT_GT(wrong.diso, right.diso);
  EXPECT_LT(wrong.orientation, right.orientation);
}

}  // namespace
}  // namespace isocorr
