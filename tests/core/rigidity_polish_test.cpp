// The rigidity polish and its mirror repair on maps with known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/partial/partial_cut.h"
#include "isocorr/refinement/rigidity_polish.h"
#include "isocorr/util/kd_tree.h"
#include "refinement_fixtures.h"
#include "spectral_test_shapes.h"

namespace isocorr {
namespace {

using test_support::exact_and_near;
using test_support::spectral_options;
using test_support::TwistedCopy;

// A map of a rotated, scaled copy with every image moved to a random neighbour (the
// nearest-neighbour noise of a spectral map) is made rigid again: every vertex comes back
// to its true image, both ways.
TEST(RigidityPolish, RemovesPerVertexNoiseFromAMapOfARigidCopy) {
  const TriangleMesh blob = limbed_blob(4);
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 1.7, 5);
  const auto source = PreprocessedShape::build(blob, spectral_options());
  const auto target = PreprocessedShape::build(copy.mesh, spectral_options());
  std::vector<int> inverse(copy.permutation.size());
  for (size_t v = 0; v < inverse.size(); ++v) inverse[copy.permutation[v]] = static_cast<int>(v);
  std::mt19937 random(11);
  auto random_neighbour = [&](const MeshTopology& topology, int v) {
    const int count = static_cast<int>(topology.neighbours_end(v) - topology.neighbours_begin(v));
    return topology.neighbours_begin(v)[std::uniform_int_distribution<int>(0, count - 1)(random)];
  };
  SpectralMap map;
  for (int v = 0; v < blob.num_vertices(); ++v)
    map.image.push_back(random_neighbour(target->geodesics().topology(), copy.permutation[v]));
  for (int w = 0; w < copy.mesh.num_vertices(); ++w)
    map.reverse_image.push_back(random_neighbour(source->geodesics().topology(), inverse[w]));
  ASSERT_LT(exact_and_near(map.image, copy.permutation, target->geodesics().topology()).first, 0.01);

  RigidityOptions options;
  rigidity_polish(*source, *target, options, map);
  EXPECT_GE(exact_and_near(map.image, copy.permutation, target->geodesics().topology()).first, 0.99);
  EXPECT_GE(exact_and_near(map.reverse_image, inverse, source->geodesics().topology()).first, 0.99);
  ASSERT_EQ(map.residual.size(), map.image.size());
  ASSERT_EQ(map.reverse_residual.size(), map.reverse_image.size());
  EXPECT_LT(*std::max_element(map.residual.begin(), map.residual.end()), 0.01);
}

// A part of the creature (60% of it, a geodesic ball removed) matched to a rotated copy of
// the whole at 1.7 times its size, every image moved to a random neighbour: at the part's
// scale, given, the polish brings every vertex back to its true image, and the forward map
// alone is made when no reverse map is asked for.
TEST(RigidityPolish, RemovesNoiseFromAPartMapAtTheGivenScale) {
  const TriangleMesh blob = limbed_blob(4);
  const PartialShape part = cut_partial_shape(blob, {CutKind::kGeodesicBall, 0.6, 1, 3});
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 1.7, 5);
  const auto source = PreprocessedShape::build(part.mesh, spectral_options());
  const auto target = PreprocessedShape::build(copy.mesh, spectral_options());
  std::vector<int> truth;
  for (const int v : part.full_vertex) truth.push_back(copy.permutation[v]);
  std::mt19937 random(13);
  const MeshTopology& topology = target->geodesics().topology();
  SpectralMap map;
  for (const int t : truth) {
    const int count = static_cast<int>(topology.neighbours_end(t) - topology.neighbours_begin(t));
    map.image.push_back(topology.neighbours_begin(t)[std::uniform_int_distribution<int>(0, count - 1)(random)]);
  }
  ASSERT_LT(exact_and_near(map.image, truth, topology).first, 0.01);

  RigidityOptions options;
  // Target length per source length, 1 / kappa, between the normalised meshes.
  const double kappa = length_ratio_normalised(1 / 1.7, source->clean().normalisation, target->clean().normalisation);
  RigidityPolish(*source, *target, options, 1 / kappa).apply(map);
  EXPECT_GE(exact_and_near(map.image, truth, topology).first, 0.99);
  EXPECT_TRUE(map.reverse_image.empty());
  ASSERT_EQ(map.residual.size(), map.image.size());
  EXPECT_LT(*std::max_element(map.residual.begin(), map.residual.end()), 0.01);
}

// A 10-degree twist is pulled back most of the way.
TEST(RigidityPolish, PullsBackASmoothTwist) {
  TwistedCopy twist(10);
  const double before = twist.mean_error(twist.map.image);
  RigidityOptions options;
  rigidity_polish(*twist.source, *twist.target, options, twist.map);
  EXPECT_LT(twist.mean_error(twist.map.image), 0.5 * before);
}

// The creature and a rotated copy, with the true map except on a band around its longest
// limb, between the tip and the body, whose images are mirrored: each band vertex sent where
// its point reflected through a plane along the limb lies (what a spectral map does to a
// shin, held right at the knee and the ankle).
struct MirroredBand {
  MirroredBand()
      : blob(limbed_blob(4)),
        copy(rotated_scaled_renumbered(blob, 1.0, 7)),
        source(PreprocessedShape::build(blob, spectral_options())),
        target(PreprocessedShape::build(copy.mesh, spectral_options())) {
    const TriangleMesh sphere = icosphere(4);  // the creature before its limbs grew, same numbering
    const Eigen::Vector3d limb = Eigen::Vector3d(1, 0.2, 0.1).normalized();
    const Eigen::Vector3d mirror_normal = limb.cross(Eigen::Vector3d::UnitZ()).normalized();
    std::vector<int> ids(blob.num_vertices());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<int>(i);
    const std::vector<Eigen::Vector3d> points(blob.vertices.begin(), blob.vertices.end());
    const KdTree tree(points, ids);
    map.image = copy.permutation;
    for (int v = 0; v < blob.num_vertices(); ++v) {
      const double angle = std::acos(std::clamp(sphere.vertices[v].dot(limb), -1.0, 1.0));
      if (angle < 0.25 || angle > 0.55) continue;
      band.push_back(v);
      const Eigen::Vector3d& p = points[v];
      map.image[v] = copy.permutation[tree.nearest(p - 2 * p.dot(mirror_normal) * mirror_normal)];
    }
    std::vector<int> inverse(copy.permutation.size());
    for (size_t v = 0; v < inverse.size(); ++v) inverse[copy.permutation[v]] = static_cast<int>(v);
    map.reverse_image = inverse;
  }
  // Share of the band's vertices sent to their true image or one of its neighbours.
  double band_right(const std::vector<int>& image) const {
    std::vector<int> band_image, band_truth;
    for (const int v : band) band_image.push_back(image[v]), band_truth.push_back(copy.permutation[v]);
    return exact_and_near(band_image, band_truth, target->geodesics().topology()).second;
  }

  TriangleMesh blob;
  RenumberedCopy copy;
  std::shared_ptr<const PreprocessedShape> source, target;
  std::vector<int> band;
  SpectralMap map;
};

// The mirrored band is a fold the polish alone settles in; placed again from the limb's
// tip and its root, it comes back to the truth, and that end state wins on energy.
TEST(RigidityPolish, UnfoldsAMirroredSegmentHeldAtBothEnds) {
  MirroredBand mirrored;
  ASSERT_GE(mirrored.band.size(), 100u);
  ASSERT_LT(mirrored.band_right(mirrored.map.image), 0.3);
  RigidityOptions options;
  const JobControl two_workers = JobControl().with_threads(2);

  SpectralMap folded = mirrored.map;
  options.mirror_repair = false;
  const MirrorRepair off = rigidity_polish(*mirrored.source, *mirrored.target, options, folded, two_workers);
  EXPECT_EQ(off.segments, 0);
  EXPECT_LT(mirrored.band_right(folded.image), 0.5);

  SpectralMap unfolded = mirrored.map;
  options.mirror_repair = true;
  const MirrorRepair on = rigidity_polish(*mirrored.source, *mirrored.target, options, unfolded, two_workers);
  EXPECT_GE(on.reversed_vertices, 50);
  EXPECT_EQ(on.segments, 1);
  EXPECT_TRUE(on.kept);
  EXPECT_GE(mirrored.band_right(unfolded.image), 0.95);
  EXPECT_GE(exact_and_near(unfolded.image, mirrored.copy.permutation, mirrored.target->geodesics().topology()).second,
            0.98);

  // The folded and the unfolded polish run side by side on two workers, one after the
  // other on one: the same map either way.
  SpectralMap alone = mirrored.map;
  EXPECT_TRUE(rigidity_polish(*mirrored.source, *mirrored.target, options, alone, JobControl().with_threads(1)).kept);
  EXPECT_EQ(alone.image, unfolded.image);
  EXPECT_EQ(alone.reverse_image, unfolded.reverse_image);
}

// On the true map there is no mirrored segment: the polish is the plain one, and the
// unfolding alone leaves the map as it is. On the mirrored band the unfolding alone, without
// any polish, already sends the band where it belongs.
TEST(RigidityPolish, UnfoldsOnlyMirroredSegments) {
  MirroredBand mirrored;
  SpectralMap truth;
  truth.image = mirrored.copy.permutation;
  truth.reverse_image = mirrored.map.reverse_image;
  RigidityOptions options;
  const RigidityPolish polish(*mirrored.source, *mirrored.target, options);
  SpectralMap untouched = truth;
  EXPECT_EQ(polish.unfold_mirrors(untouched).segments, 0);
  EXPECT_EQ(untouched.image, truth.image);

  const MirrorRepair repair = polish.apply(truth);
  EXPECT_EQ(repair.segments, 0);
  EXPECT_FALSE(repair.kept);
  EXPECT_EQ(truth.image, mirrored.copy.permutation);

  SpectralMap unfolded = mirrored.map;
  EXPECT_EQ(polish.unfold_mirrors(unfolded).segments, 1);
  EXPECT_TRUE(unfolded.residual.empty());  // not polished
  EXPECT_GE(mirrored.band_right(unfolded.image), 0.9);
}

}  // namespace
}  // namespace isocorr
