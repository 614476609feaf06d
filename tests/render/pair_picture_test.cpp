// The picture of a map: a right map makes both halves alike, a wrong one does not.
#include "isocorr/render/pair_picture.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <numeric>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

constexpr Rgb kWhite = {255, 255, 255};

// Mean absolute difference per channel between the left half and the right half (past the
// separator column; the picture's width is odd), over pixels where either shows the mesh.
double halves_difference(const RgbImage& image, int* mesh_pixels) {
  const int half = image.width / 2;
  double sum = 0;
  int count = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < half; ++x) {
      const Rgb left = image.at(x, y), right = image.at(x + half + 1, y);
      if (left == kWhite && right == kWhite) continue;
      ++count;
      for (int c = 0; c < 3; ++c) sum += std::abs(left[c] - right[c]);
    }
  *mesh_pixels = count;
  return count ? sum / (3.0 * count) : 0;
}

class PairPicture : public ::testing::Test {
 protected:
  const TriangleMesh creature_ = limbed_blob(3);
  // The same creature turned, scaled and renumbered: its permutation is the right map.
  const RenumberedCopy moved_ = rotated_scaled_renumbered(creature_, 1.7, 7);
  PairPictureOptions options_{201, 100, "principal"};
};

TEST_F(PairPicture, TheRightMapShowsTheSameColouredShapeOnBothSides) {
  const RgbImage image = render_pair_picture(creature_, moved_.mesh, moved_.permutation, options_);
  ASSERT_EQ(image.width, 201);
  ASSERT_EQ(image.height, 100);
  int mesh_pixels = 0;
  const double difference = halves_difference(image, &mesh_pixels);
  EXPECT_GT(mesh_pixels, 1500);  // the creature fills a good part of each half
  EXPECT_LT(difference, 12) << "of " << mesh_pixels << " pixels";
  EXPECT_EQ(image.at(100, 50), (Rgb{200, 200, 200}));  // the separator
}

TEST_F(PairPicture, AWrongMapShowsOtherColours) {
  std::vector<int> wrong = moved_.permutation;
  std::rotate(wrong.begin(), wrong.begin() + wrong.size() / 2, wrong.end());
  int mesh_pixels = 0;
  const double right = halves_difference(render_pair_picture(creature_, moved_.mesh, moved_.permutation, options_), &mesh_pixels);
  const double wrong_difference = halves_difference(render_pair_picture(creature_, moved_.mesh, wrong, options_), &mesh_pixels);
  EXPECT_GT(wrong_difference, 3 * right);
}

// A body symmetric between left (-x) and right (+x) only: longest along y, with its top
// unlike its bottom and its front (+z) unlike its back.
TriangleMesh left_right_symmetric_body() {
  TriangleMesh body = icosphere(3);  // the icosahedron's vertex set is symmetric in x
  for (Vec3& p : body.vertices) p = Vec3(0.6 * p.x(), 1.5 * p.y() + 0.4 * p.z() * p.z(), 0.5 * p.z() + 0.3 * p.y() * p.y());
  return body;
}

TEST_F(PairPicture, AMirroredMapShowsLeftAndRightColoursSwapped) {
  const TriangleMesh body = left_right_symmetric_body();
  const TriangleMesh sphere = icosphere(3);
  std::vector<int> identity(body.vertices.size()), mirrored(body.vertices.size());
  std::iota(identity.begin(), identity.end(), 0);
  for (size_t v = 0; v < sphere.vertices.size(); ++v) {  // the vertex at (-x, y, z)
    const Vec3& p = sphere.vertices[v];
    double best = 1e9;
    for (size_t w = 0; w < sphere.vertices.size(); ++w) {
      const double d = (sphere.vertices[w] - Vec3(-p.x(), p.y(), p.z())).norm();
      if (d < best) best = d, mirrored[v] = static_cast<int>(w);
    }
    ASSERT_LT(best, 1e-9);
  }
  int mesh_pixels = 0;
  const double right = halves_difference(render_pair_picture(body, body, identity, options_), &mesh_pixels);
  const double swapped = halves_difference(render_pair_picture(body, body, mirrored, options_), &mesh_pixels);
  EXPECT_LT(right, 1);
  // Were the source turned round to match its images, the colours would agree again.
  EXPECT_GT(swapped, 20) << "of " << mesh_pixels << " pixels";
}

TEST_F(PairPicture, RefusesMapsThatDoNotFitAndUnusableSizes) {
  std::vector<int> short_map(moved_.permutation.begin(), moved_.permutation.end() - 1);
  std::vector<int> outside = moved_.permutation;
  outside[5] = moved_.mesh.num_vertices();
  EXPECT_THROW(render_pair_picture(creature_, moved_.mesh, short_map, options_), InputError);
  try {
    render_pair_picture(creature_, moved_.mesh, outside, options_);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("source vertex 5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(render_pair_picture(creature_, moved_.mesh, moved_.permutation, {8, 100, "principal"}), InputError);
  EXPECT_THROW(render_pair_picture(creature_, moved_.mesh, moved_.permutation, {100, 100, "oblique"}), InputError);
}

}  // namespace
}  // namespace isocorr
