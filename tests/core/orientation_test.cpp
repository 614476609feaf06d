// The handedness tests on a shape with a known answer: an asymmetric mesh against itself
// (every triangle keeps its handedness) and against its mirror image with the same
// numbering (every triangle reverses it).
#include "isocorr/matching/orientation.h"

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"

namespace isocorr {
namespace {

TriangleMesh mirrored(TriangleMesh mesh) {
  for (Vec3& p : mesh.vertices) p.x() = -p.x();
  for (Face& f : mesh.faces) std::swap(f[1], f[2]);  // keep the faces pointing outward
  return mesh;
}

class HandednessOnBlob : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const TriangleMesh blob = limbed_blob(3);
    shape_ = PreprocessedShape::build(blob, PreprocessOptions{});
    mirror_ = PreprocessedShape::build(mirrored(blob), PreprocessOptions{});
  }
  static void TearDownTestSuite() {
    shape_.reset();
    mirror_.reset();
  }
  // Every sample of the shape paired with the same vertex of `target` (same numbering).
  static std::vector<SamplePair> identity_pairs() {
    std::vector<SamplePair> pairs;
    for (int s = 0; s < shape_->num_samples(); ++s) pairs.push_back({s, 0, 0.f, shape_->sample_vertex(s)});
    return pairs;
  }
  // Share of samples whose own vertex on `target` passes the guard built from all the
  // coarser samples (those of earlier steps) as matched pairs.
  static double accepted_share(const PreprocessedShape& target) {
    const std::vector<SamplePair> all = identity_pairs();
    int accepted = 0, tested = 0;
    for (int s = 0; s < shape_->num_samples(); ++s) {
      std::vector<SamplePair> matched;
      for (const SamplePair& p : all)
        if (shape_->sample_step(p.source_sample) < shape_->sample_step(s)) matched.push_back(p);
      if (matched.size() < 3) continue;
      const HandednessGuard guard(*shape_, target, matched, shape_->sample_vertex(s), 0.02f);
      accepted += guard.accepts(shape_->sample_vertex(s));
      ++tested;
    }
    EXPECT_GT(tested, 20);
    return static_cast<double>(accepted) / tested;
  }
  static std::shared_ptr<const PreprocessedShape> shape_;
  static std::shared_ptr<const PreprocessedShape> mirror_;
};
std::shared_ptr<const PreprocessedShape> HandednessOnBlob::shape_;
std::shared_ptr<const PreprocessedShape> HandednessOnBlob::mirror_;

TEST_F(HandednessOnBlob, SampleTrianglesKeepHandednessOnlyWithoutMirror) {
  EXPECT_GT(orientation_agreement(*shape_, *shape_, identity_pairs()), 0.95);
  EXPECT_LT(orientation_agreement(*shape_, *mirror_, identity_pairs()), 0.05);
}

TEST_F(HandednessOnBlob, GuardAcceptsTrueImagesAndRejectsMirrorImages) {
  EXPECT_GT(accepted_share(*shape_), 0.95);
  EXPECT_LT(accepted_share(*mirror_), 0.05);
}

// A map made on some vertices only (the part search's rough candidates) is judged on the
// faces whose three vertices have images: the rest (-1) neither count nor crash.
TEST_F(HandednessOnBlob, FacesWithUnmappedVerticesAreLeftOut) {
  const int n = shape_->mesh().num_vertices();
  std::vector<int> half(n), mirror_half(n);
  for (int v = 0; v < n; ++v) half[v] = v % 3 ? v : -1;
  const double kept =
      dense_orientation_agreement(shape_->mesh(), shape_->normals(), shape_->mesh(), shape_->normals(), half);
  const double mirrored_kept =
      dense_orientation_agreement(shape_->mesh(), shape_->normals(), mirror_->mesh(), mirror_->normals(), half);
  std::vector<int> none(n, -1);
  EXPECT_GT(kept, 0.99);
  EXPECT_LT(mirrored_kept, 0.01);
  EXPECT_EQ(dense_orientation_agreement(shape_->mesh(), shape_->normals(), shape_->mesh(), shape_->normals(), none),
            0.5);  // nothing to judge
}

// The neighbourhood test on a noisy dense map: each image moved to a random neighbour folds
// many single faces, but neighbourhoods a few rings wide keep their handedness; the mirror
// with the same noise reverses them.
TEST_F(HandednessOnBlob, NeighbourhoodsSeeThroughPerVertexNoise) {
  const int n = shape_->mesh().num_vertices();
  const MeshTopology& topology = shape_->geodesics().topology();
  std::vector<int> noisy(n), every(n);
  for (int v = 0; v < n; ++v) {
    every[v] = v;
    const int degree = static_cast<int>(topology.neighbours_end(v) - topology.neighbours_begin(v));
    noisy[v] = v % 2 ? topology.neighbours_begin(v)[(v / 2) % degree] : v;
  }
  const double radius = 0.05 * shape_->diameter();
  const double faces_kept =
      dense_orientation_agreement(shape_->mesh(), shape_->normals(), shape_->mesh(), shape_->normals(), noisy);
  const double kept = neighbourhood_orientation_agreement(shape_->mesh(), shape_->normals(), topology, shape_->mesh(),
                                                          shape_->normals(), noisy, every, radius, 2);
  const double mirrored_kept = neighbourhood_orientation_agreement(
      shape_->mesh(), shape_->normals(), topology, mirror_->mesh(), mirror_->normals(), noisy, every, radius, 2);
  EXPECT_LT(faces_kept, 0.9);
  EXPECT_GT(kept, 0.95);
  EXPECT_LT(mirrored_kept, 0.05);
}

}  // namespace
}  // namespace isocorr
