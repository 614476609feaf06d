// The C2F dense level on a pair with a known answer: from the true sample pairs every vertex
// finds its true image (or one next to it), both ways; with a tenth of the pairs sent astray
// the outlier rule keeps the map right.
#include "isocorr/matching/dense_map.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "creature_pair.h"

namespace isocorr {
namespace {

using testing::CreaturePair;

class DenseMapOnCreature : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { pair_ = new CreaturePair(3); }
  static void TearDownTestSuite() { delete pair_; }

  // Every source sample paired with the target vertex of its true image.
  static std::vector<SamplePair> true_pairs() {
    std::vector<SamplePair> pairs;
    for (int i = 0; i < pair_->source->num_samples(); ++i) {
      SamplePair p;
      p.source_sample = i;
      p.target_sample = pair_->true_target_sample(i, pair_->target->num_samples());
      p.target_vertex = pair_->truth[pair_->source->sample_vertex(i)];
      pairs.push_back(p);
    }
    return pairs;
  }

  // Share of source vertices whose image lies within `radius` (fraction of the diameter) of
  // the true one.
  static double share_within(const std::vector<int>& forward, double radius) {
    int within = 0;
    for (size_t v = 0; v < forward.size(); ++v) within += pair_->error(static_cast<int>(v), forward[v]) <= radius;
    return static_cast<double>(within) / forward.size();
  }

  static CreaturePair* pair_;
};
CreaturePair* DenseMapOnCreature::pair_ = nullptr;

TEST_F(DenseMapOnCreature, TrueSamplePairsGiveTheTrueMapBothWays) {
  DenseOptions options;
  const DenseMap map = compute_dense_map(*pair_->source, *pair_->target, true_pairs(), options, JobControl{});
  ASSERT_EQ(map.forward.size(), pair_->truth.size());
  ASSERT_EQ(map.reverse.size(), static_cast<size_t>(pair_->target->mesh().num_vertices()));
  EXPECT_GE(share_within(map.forward, 0.03), 0.97);
  int exact = 0;
  for (size_t v = 0; v < map.forward.size(); ++v) exact += map.forward[v] == pair_->truth[v];
  EXPECT_GE(exact, 0.5 * map.forward.size());
  // The reverse map sends each target vertex back to a source vertex whose true image is near.
  int back = 0;
  for (size_t t = 0; t < map.reverse.size(); ++t)
    back += pair_->error(map.reverse[t], static_cast<int>(t)) <= 0.03;
  EXPECT_GE(back, 0.97 * map.reverse.size());
  EXPECT_EQ(map.forward_diso.size(), map.forward.size());
}

TEST_F(DenseMapOnCreature, ATenthOfThePairsAstrayIsOutvoted) {
  std::vector<SamplePair> pairs = true_pairs();
  std::mt19937 random(17);
  std::uniform_int_distribution<int> any_vertex(0, pair_->target->mesh().num_vertices() - 1);
  for (size_t k = 3; k < pairs.size(); k += 10) {
    pairs[k].target_vertex = any_vertex(random);
    pairs[k].target_sample = 0;
  }
  DenseOptions options;
  const DenseMap map = compute_dense_map(*pair_->source, *pair_->target, pairs, options, JobControl{});
  EXPECT_GE(share_within(map.forward, 0.05), 0.95);
}

}  // namespace
}  // namespace isocorr
