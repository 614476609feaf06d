// Evenly spaced salient sampling: spacing holds at every step and samples follow saliency.
#include "isocorr/sampling/salient_sampling.h"

#include <atomic>

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/sampling/saliency.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

TEST(SalientSampling, SamplesKeepTheirStepRadiusApart) {
  const TriangleMesh sphere = icosphere(4);
  const MeshTopology topology(sphere);
  const FastMarching fmm(sphere, topology);
  std::vector<int> order(sphere.num_vertices());
  for (int v = 0; v < sphere.num_vertices(); ++v) order[v] = v;
  SamplingSchedule schedule{{0.9, 0.5, 0.3}, {0, 0, 0}};
  const SampleSet samples = evenly_spaced_salient_sampling(fmm, order, schedule);
  ASSERT_GT(samples.vertices.size(), 20u);
  EXPECT_EQ(samples.vertices[0], 0);  // the most salient vertex comes first
  for (size_t i = 0; i < samples.vertices.size(); ++i) {
    const std::vector<float> d = fmm.distance_field(samples.vertices[i]);
    for (size_t j = 0; j < i; ++j) {
      // A sample accepted at step s is at least radius(s) from all earlier samples.
      EXPECT_GE(d[samples.vertices[j]], schedule.radii[samples.step[i]] - 1e-4);
    }
  }
  // Coverage: every vertex lies within the last radius of some sample.
  std::vector<float> nearest(sphere.num_vertices(), kUnreached);
  for (int s : samples.vertices) {
    const auto d = fmm.distance_field(s);
    for (int v = 0; v < sphere.num_vertices(); ++v) nearest[v] = std::min(nearest[v], d[v]);
  }
  for (float d : nearest) EXPECT_LT(d, 0.3f + 1e-4f);
}

TEST(Saliency, ExtremitiesAreTheLimbTips) {
  const TriangleMesh blob = limbed_blob(4);
  const MeshTopology topology(blob);
  const FastMarching fmm(blob, topology);
  const Saliency saliency = compute_saliency(fmm, SaliencyOptions{}, 2);
  // Five limbs: the five most salient extremities are their tips, far from the centre.
  ASSERT_GE(saliency.extremities.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_GT(blob.vertices[saliency.extremities[i]].norm(), 1.2);  // body radius <= 1
  EXPECT_EQ(saliency.order.size(), static_cast<size_t>(blob.num_vertices()));
}

TEST(Saliency, CancelledJobStopsBetweenFields) {
  const TriangleMesh blob = limbed_blob(3);
  const MeshTopology topology(blob);
  const FastMarching fmm(blob, topology);
  const std::atomic<bool> cancel{true};
  JobControl control;
  control.cancel_requested = &cancel;
  EXPECT_THROW(compute_saliency(fmm, SaliencyOptions{}, 2, control), Cancelled);
}

}  // namespace
}  // namespace isocorr
