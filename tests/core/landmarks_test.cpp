// Landmarks: their validation, their measures, and that one landmark decides between two
// equally right maps of a symmetric shape.
#include "isocorr/transfer/landmarks.h"

#include <gtest/gtest.h>


#include <nlohmann/json.hpp>

#include "isocorr/matching/level0_search.h"
#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/pipeline/run_match.h"
#include "isocorr/settings/settings_json.h"
#include "isocorr/settings/settings_schema.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

std::string problem_of(const std::vector<Landmark>& landmarks, int source_vertices = -1, int target_vertices = -1) {
  try {
    validate_landmarks(landmarks, source_vertices, target_vertices);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(LandmarkValidation, NamesTheOffendingEntry) {
  EXPECT_EQ(problem_of({{0, 1}, {2, 3}}), "");
  EXPECT_EQ(problem_of({{0, 1}, {2, 3}}, 3, 4), "");
  EXPECT_EQ(problem_of({{0, 1}, {-2, 3}}), "landmarks[1]: source vertex -2 is negative");
  EXPECT_EQ(problem_of({{0, 1}, {2, 3}, {5, 3}}, 10, 10),
            "landmarks[2]: target vertex 3 is given two sources, 2 and 5 (landmarks[1])");
  EXPECT_EQ(problem_of({{0, 1}, {0, 4}}), "landmarks[1]: source vertex 0 is given two targets, 1 and 4 (landmarks[0])");
  EXPECT_EQ(problem_of({{0, 1}, {2, 3}, {0, 1}}), "landmarks[2]: the pair 0 1 is given twice (landmarks[0])");
  EXPECT_EQ(problem_of({{0, 1}, {2, 3}}, 2, 10),
            "landmarks[1]: source vertex 2 is out of range: the source mesh has 2 vertices");
  EXPECT_EQ(problem_of({{0, 9}}, 2, 9), "landmarks[0]: target vertex 9 is out of range: the target mesh has 9 vertices");
  EXPECT_NE(problem_of(std::vector<Landmark>(kMaxLandmarks + 1)).find("more than"), std::string::npos);
}

TEST(LandmarkValidation, SettingsValidateThemAndCarryThemThroughJson) {
  MatchSettings settings;
  settings.landmarks = {{3, 4}, {3, 5}};
  EXPECT_THROW(settings.validate(), InputError);
  settings.landmarks = {{3, 4}, {7, 5}};
  EXPECT_NO_THROW(settings.validate());

  const nlohmann::json json = settings_to_json(settings);
  EXPECT_EQ(json["landmarks"][1]["source_vertex"], 7);
  const MatchSettings back = settings_from_json(json);
  EXPECT_EQ(back.landmarks, settings.landmarks);
  EXPECT_TRUE(same_settings(back, settings));
  EXPECT_FALSE(same_settings(back, MatchSettings{}));
  // Without landmarks the JSON is what it was before they existed.
  EXPECT_FALSE(settings_to_json(MatchSettings{}).contains("landmarks"));
  // Per match: the shape cache key leaves them out.
  EXPECT_EQ(settings_key(settings, SettingScope::kPreprocess), settings_key(MatchSettings{}, SettingScope::kPreprocess));

  for (const char* bad : {R"({"landmarks": 3})", R"({"landmarks": [[1, 2]]})",
                          R"({"landmarks": [{"source_vertex": 1}]})",
                          R"({"landmarks": [{"source_vertex": 1, "target_vertex": 4294967296}]})"})
    EXPECT_THROW(settings_from_json(nlohmann::json::parse(bad)), InputError) << bad;
}

TEST(LandmarkLevel0, DropsDisagreeingMapsButNeverAll) {
  std::vector<Level0Map> maps(4);
  for (int i = 0; i < 4; ++i) maps[i].diso = 0.01 * i;
  std::vector<Level0Map> some = maps;
  const Level0Drop dropped = drop_level0_maps(some, {0.3, 0.05, 0.2, 0.1}, 0.15);
  EXPECT_EQ(dropped.dropped, 2);
  EXPECT_FALSE(dropped.none_agreed);
  ASSERT_EQ(some.size(), 2u);
  EXPECT_EQ(some[0].diso, 0.01);  // the order of the rest is kept
  EXPECT_EQ(some[1].diso, 0.03);

  const Level0Drop all = drop_level0_maps(maps, {0.3, 0.5, 0.2, 0.4}, 0.15);
  EXPECT_EQ(all.dropped, 3);
  EXPECT_TRUE(all.none_agreed);
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_EQ(maps[0].diso, 0.02);  // the least disagreeing
}

// The twofold creature (procedural_meshes.h) and a rotated, scaled, renumbered copy: the
// true map and the true map after the symmetry's turn are both isometries that keep
// handedness, so the engine's evidence cannot prefer either; a landmark on a limb can.
class LandmarksOnTwofoldBlob : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    blob_ = new TriangleMesh(twofold_blob(3));
    copy_ = new RenumberedCopy(rotated_scaled_renumbered(*blob_, 1.7, 7));
    // The turn's partner of each vertex: the vertex at (-x, -y, z).
    turned_ = new std::vector<int>(blob_->num_vertices());
    for (int v = 0; v < blob_->num_vertices(); ++v) {
      const Vec3& p = blob_->vertices[v];
      const Vec3 twin(-p.x(), -p.y(), p.z());
      int& nearest = (*turned_)[v];
      for (int w = 1; w < blob_->num_vertices(); ++w)
        if ((blob_->vertices[w] - twin).norm() < (blob_->vertices[nearest] - twin).norm()) nearest = w;
    }
  }
  static void TearDownTestSuite() {
    delete blob_;
    delete copy_;
    delete turned_;
  }

  // The tip of the long limb (the vertex farthest along its direction) and of the short one.
  static int tip(const Vec3& direction) {
    int best = 0;
    for (int v = 1; v < blob_->num_vertices(); ++v)
      if (blob_->vertices[v].dot(direction) > blob_->vertices[best].dot(direction)) best = v;
    return best;
  }

  // Share of source vertices whose image is `expected[v]`'s copy.
  static double share_exact(const std::vector<int>& forward, const std::vector<int>& expected_in_source) {
    int exact = 0;
    for (size_t v = 0; v < forward.size(); ++v) exact += forward[v] == copy_->permutation[expected_in_source[v]];
    return static_cast<double>(exact) / forward.size();
  }

  static MatchResult match_with(const std::vector<Landmark>& landmarks, MatchMethod method = MatchMethod::kFull) {
    MatchSettings settings;
    settings.threads = 2;
    settings.method = method;
    settings.landmarks = landmarks;
    return match_meshes(*blob_, copy_->mesh, settings);
  }

  static TriangleMesh* blob_;
  static RenumberedCopy* copy_;
  static std::vector<int>* turned_;
};
TriangleMesh* LandmarksOnTwofoldBlob::blob_ = nullptr;
RenumberedCopy* LandmarksOnTwofoldBlob::copy_ = nullptr;
std::vector<int>* LandmarksOnTwofoldBlob::turned_ = nullptr;

TEST_F(LandmarksOnTwofoldBlob, TheShapeIsExactlySymmetric) {
  std::vector<int> identity(blob_->num_vertices());
  for (int v = 0; v < blob_->num_vertices(); ++v) identity[v] = v;
  EXPECT_NE(*turned_, identity);
  for (int v = 0; v < blob_->num_vertices(); ++v) {
    ASSERT_EQ((*turned_)[(*turned_)[v]], v);
    const Vec3& p = blob_->vertices[v];
    EXPECT_LT((blob_->vertices[(*turned_)[v]] - Vec3(-p.x(), -p.y(), p.z())).norm(), 1e-12);
  }
}

TEST_F(LandmarksOnTwofoldBlob, OneLandmarkDecidesBetweenTheTwoRightMaps) {
  std::vector<int> identity(blob_->num_vertices());
  for (int v = 0; v < blob_->num_vertices(); ++v) identity[v] = v;
  const int long_tip = tip(Vec3(1, 0.3, 0.2));

  const MatchResult unconstrained = match_with({});
  // A coin toss between two equally right maps: whichever it is, it is one of them.
  EXPECT_GT(std::max(share_exact(unconstrained.output.forward, identity),
                     share_exact(unconstrained.output.forward, *turned_)),
            0.95);

  const MatchResult right = match_with({{long_tip, copy_->permutation[long_tip]}});
  EXPECT_GT(share_exact(right.output.forward, identity), 0.95);
  EXPECT_GT(right.diagnostics.landmarks.level0_dropped, 0);
  EXPECT_TRUE(right.diagnostics.landmarks.honoured);
  ASSERT_EQ(right.diagnostics.landmarks.chosen_errors.size(), 1u);
  EXPECT_LT(right.diagnostics.landmarks.chosen_errors[0], kLandmarkTolerance);
  const nlohmann::json report = nlohmann::json::parse(right.output.report_json);
  EXPECT_EQ(report["landmarks"]["level0_maps_dropped"], right.diagnostics.landmarks.level0_dropped);
  EXPECT_EQ(report["landmarks"]["chosen_map_honours_them"], true);
  EXPECT_EQ(report["settings"]["landmarks"][0]["source_vertex"], long_tip);

  // A landmark that says the long limb goes to its twin gives the turned map.
  const MatchResult turned = match_with({{long_tip, copy_->permutation[(*turned_)[long_tip]]}});
  EXPECT_GT(share_exact(turned.output.forward, *turned_), 0.95);
  EXPECT_EQ(turned.output.forward[long_tip], copy_->permutation[(*turned_)[long_tip]]);
  EXPECT_EQ(turned.output.reverse[copy_->permutation[(*turned_)[long_tip]]], long_tip);
}

// With the part methods the part search's map and the complete pipeline's compete on the
// landmarks first, and the kept one is pinned.
TEST_F(LandmarksOnTwofoldBlob, TheyDecideAsPartsToo) {
  const int long_tip = tip(Vec3(1, 0.3, 0.2));
  for (const MatchMethod method : {MatchMethod::kPart, MatchMethod::kRavac}) {
    const MatchResult turned = match_with({{long_tip, copy_->permutation[(*turned_)[long_tip]]}}, method);
    EXPECT_GT(share_exact(turned.output.forward, *turned_), 0.95);
    EXPECT_EQ(turned.output.forward[long_tip], copy_->permutation[(*turned_)[long_tip]]);
    EXPECT_EQ(turned.diagnostics.landmarks.count, 1);
    EXPECT_TRUE(turned.diagnostics.landmarks.honoured);
  }
}

TEST_F(LandmarksOnTwofoldBlob, OutOfRangeLandmarksAreInputErrors) {
  EXPECT_THROW(match_with({{blob_->num_vertices(), 0}}), InputError);
}

}  // namespace
}  // namespace isocorr
