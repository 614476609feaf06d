// The whole engine on a shape with a known answer: an asymmetric mesh against a rotated,
// scaled, renumbered copy of itself must give the permutation back.
#include "isocorr/pipeline/run_match.h"

#include <atomic>

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"

namespace isocorr {
namespace {

class MatcherOnBlob : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    blob_ = new TriangleMesh(limbed_blob(4));
    copy_ = new RenumberedCopy(rotated_scaled_renumbered(*blob_, 2.5, 11));
  }
  static void TearDownTestSuite() {
    delete blob_;
    delete copy_;
  }
  static TriangleMesh* blob_;
  static RenumberedCopy* copy_;
};
TriangleMesh* MatcherOnBlob::blob_ = nullptr;
RenumberedCopy* MatcherOnBlob::copy_ = nullptr;

TEST_F(MatcherOnBlob, RecoversThePermutation) {
  MatchSettings settings;
  settings.threads = 2;
  const MatchResult result = match_meshes(*blob_, copy_->mesh, settings);
  ASSERT_EQ(result.output.forward.size(), blob_->vertices.size());
  ASSERT_EQ(result.output.reverse.size(), blob_->vertices.size());

  const MeshTopology topology(copy_->mesh);
  int exact = 0, within_ring = 0;
  for (size_t v = 0; v < result.output.forward.size(); ++v) {
    const int truth = copy_->permutation[v];
    const int got = result.output.forward[v];
    if (got == truth) {
      ++exact;
      continue;
    }
    for (const int* w = topology.neighbours_begin(truth); w != topology.neighbours_end(truth); ++w)
      if (*w == got) ++within_ring;
  }
  const int n = static_cast<int>(result.output.forward.size());
  EXPECT_GE(exact, 0.99 * n) << "exact " << exact << " of " << n;
  EXPECT_EQ(exact + within_ring, n);
  EXPECT_GT(result.quality.orientation, 0.9);

  // The reverse map is the inverse permutation on the same terms.
  int reverse_exact = 0;
  for (size_t v = 0; v < result.output.forward.size(); ++v) reverse_exact += result.output.reverse[copy_->permutation[v]] == static_cast<int>(v);
  EXPECT_GE(reverse_exact, 0.99 * n);
}

TEST_F(MatcherOnBlob, ResultDoesNotDependOnThreadCount) {
  MatchSettings one, two;
  one.threads = 1;
  two.threads = 2;
  const MatchResult a = match_meshes(*blob_, copy_->mesh, one);
  const MatchResult b = match_meshes(*blob_, copy_->mesh, two);
  EXPECT_EQ(a.output.forward, b.output.forward);
  EXPECT_EQ(a.output.reverse, b.output.reverse);
  EXPECT_EQ(a.diagnostics.tracking.chosen, b.diagnostics.tracking.chosen);
}

TEST_F(MatcherOnBlob, ReportsProgressAndHonoursCancellation) {
  std::atomic<bool> cancel{false};
  JobControl control;
  // Atomic: the tracking stage reports from its worker threads (a plain int raced, TSan).
  std::atomic<int> reports{0};
  control.on_progress = [&](const Progress& p) {
    ++reports;
    if (p.stage == "tracking") cancel = true;
  };
  control.cancel_requested = &cancel;
  EXPECT_THROW(match_meshes(*blob_, copy_->mesh, MatchSettings{}, control), Cancelled);
  EXPECT_GT(reports.load(), 2);
}

// A repaired input is something to act on, set apart from the remarks on routine steps
// (which a log shows as information, not as warnings).
TEST_F(MatcherOnBlob, InputRepairsAreWarningsAndRoutineStepsAreNotes) {
  TriangleMesh target = copy_->mesh;
  target.vertices.push_back(target.vertices.front() + Vec3(5, 5, 5));  // used by no face
  MatchSettings settings;
  settings.threads = 2;
  const MatchResult result = match_meshes(*blob_, target, settings);
  ASSERT_EQ(result.messages.warnings.size(), 1u);
  EXPECT_EQ(result.messages.warnings[0].rfind("target: ", 0), 0u) << result.messages.warnings[0];
  EXPECT_NE(result.messages.warnings[0].find("dropped 1 vertex used by no face"), std::string::npos) << result.messages.warnings[0];
  EXPECT_FALSE(result.messages.notes.empty());
  for (const std::string& note : result.messages.notes) EXPECT_EQ(note.find("dropped"), std::string::npos) << note;
  EXPECT_EQ(result.summary().notes.front(), result.messages.warnings[0]);

  const MatchResult clean = match_meshes(*blob_, copy_->mesh, settings);
  EXPECT_TRUE(clean.messages.warnings.empty());
}

TEST(MatcherSettings, OutOfRangeSettingsAreInputErrors) {
  MatchSettings settings;
  settings.level0_samples = 2;
  EXPECT_THROW(settings.validate(), InputError);
  settings = MatchSettings{};
  settings.level0_samples = 9;
  settings.level0_extra_targets = 2;
  EXPECT_THROW(settings.validate(), InputError);
}

}  // namespace
}  // namespace isocorr

namespace isocorr {
namespace {

// A mesh matched to itself: every distortion is zero, which must not empty the anchors.
TEST(MatcherSelfMatch, IdentityComesBack) {
  const TriangleMesh blob = limbed_blob(3);
  MatchSettings settings;
  settings.threads = 2;  // also TSan's run of the complete pipeline (scripts/sanitize.sh)
  const MatchResult result = match_meshes(blob, blob, settings);
  int exact = 0;
  for (size_t v = 0; v < result.output.forward.size(); ++v) exact += result.output.forward[v] == static_cast<int>(v);
  EXPECT_GE(exact, 0.99 * result.output.forward.size());
  EXPECT_LT(result.quality.diso, 1e-3);
}

// A mesh is matched the same at any scale: coordinates near the largest double (which once
// sent the eigensolver into an endless loop) and near the smallest normal ones (whose faces
// once all looked degenerate) give the map of the unscaled mesh.
TEST(MatcherAtAnyScale, ExtremeCoordinatesGiveTheSameMap) {
  const TriangleMesh blob = limbed_blob(3);
  const RenumberedCopy copy = rotated_scaled_renumbered(blob, 1.7, 2024);
  MatchSettings settings;
  settings.threads = 2;
  const MatchResult reference = match_meshes(blob, copy.mesh, settings);
  auto scaled = [](TriangleMesh mesh, double largest) {
    double now = 0;
    for (const Vec3& p : mesh.vertices) now = std::max(now, p.cwiseAbs().maxCoeff());
    for (Vec3& p : mesh.vertices) p = p / now * largest;
    return mesh;
  };
  for (const double largest : {1e308, 1e-160}) {
    const MatchResult result = match_meshes(scaled(blob, largest), scaled(copy.mesh, largest), settings);
    EXPECT_EQ(result.output.forward, reference.output.forward) << largest;
  }
}

}  // namespace
}  // namespace isocorr
