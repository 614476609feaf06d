// End to end on real benchmark pairs from ../shared/data: the whole engine, scored
// against ground truth the way the benchmark scores it.
#include <filesystem>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "isocorr/diagnosis/map_tearing.h"
#include "isocorr/diagnosis/verdict.h"
#include "isocorr/eval/ground_truth.h"
#include "isocorr/eval/metrics.h"
#include "isocorr/geodesic/geodesic_diameter.h"
#include "isocorr/pipeline/run_match.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/partial/partial_cut.h"
#include "isocorr/transfer/precise_map.h"
#include "isocorr/util/kd_tree.h"

#ifndef ISOCORR_SHARED_DATA_DIR
#define ISOCORR_SHARED_DATA_DIR "../shared/data"
#endif

namespace isocorr {
namespace {

BenchmarkPair listed_pair(const std::string& dir, const std::string& source, const std::string& target) {
  BenchmarkPair pair;
  for (const auto& listed : read_pairs_tsv(dir))
    if (listed.source_path == dir + "/" + source && listed.target_path == dir + "/" + target) pair = listed;
  EXPECT_FALSE(pair.gt_kind.empty()) << "pair not listed in " << dir << "/pairs.tsv";
  return pair;
}

GroundTruthScore score_on_target(const TriangleMesh& target, const std::vector<int>& forward, const GroundTruth& truth) {
  const MeshTopology topology(target);
  const FastMarching geodesics(target, topology);
  return score_against_ground_truth(target, geodesics, estimate_geodesic_diameter(geodesics), forward, truth,
                                    EvaluationOptions{});
}

GroundTruthScore match_and_score(const std::string& dataset, const std::string& source, const std::string& target,
                                 const MatchSettings& settings = {}, MatchVerdict* verdict = nullptr) {
  const std::string dir = std::string(ISOCORR_SHARED_DATA_DIR) + "/" + dataset;
  const BenchmarkPair pair = listed_pair(dir, source, target);
  const LoadedMesh s = load_mesh(pair.source_path), t = load_mesh(pair.target_path);
  const MatchResult result = match_meshes(s.mesh, t.mesh, settings);
  if (verdict) *verdict = result.verdict;
  const GroundTruth truth = load_ground_truth(dir, pair, s.mesh.num_vertices(), t.mesh.num_vertices());
  return score_on_target(t.mesh, result.output.forward, truth);
}

// The source cut by `cut` (isocorr cut), matched to the whole target with --partial, scored
// on the ground truth carried through the cut (as isocorr-bench-partial does).
GroundTruthScore match_part_and_score(const std::string& dataset, const std::string& source,
                                      const std::string& target, const CutSpec& cut) {
  const std::string dir = std::string(ISOCORR_SHARED_DATA_DIR) + "/" + dataset;
  const BenchmarkPair pair = listed_pair(dir, source, target);
  const LoadedMesh s = load_mesh(pair.source_path), t = load_mesh(pair.target_path);
  const PartialShape part = cut_partial_shape(s.mesh, cut);
  MatchSettings settings;
  settings.method = MatchMethod::kPart;
  const MatchResult result = match_meshes(part.mesh, t.mesh, settings);
  const GroundTruth truth =
      ground_truth_of_parts(load_ground_truth(dir, pair, s.mesh.num_vertices(), t.mesh.num_vertices()), part,
                            s.mesh.num_vertices(), nullptr, t.mesh.num_vertices());
  return score_on_target(t.mesh, result.output.forward, truth);
}

class RealData : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(ISOCORR_SHARED_DATA_DIR))
      GTEST_SKIP() << "benchmark data not found at " << ISOCORR_SHARED_DATA_DIR
                   << " (it sits beside the repository as ../shared/data)";
  }
};

TEST_F(RealData, ToscaWolfIsFlipFreeAndAccurate) {
  const GroundTruthScore score = match_and_score("tosca_hires", "off/wolf0.off", "off/wolf1.off");
  EXPECT_TRUE(score.flip_free) << score.flip_rule << "; mirrored " << score.mirrored_fraction;
  EXPECT_LT(score.mean_error, 0.035);
}

// With the spectral refinement: 0.0069 measured (the C2F map alone: 0.0140).
TEST_F(RealData, ScapePairIsFlipFreeAndAccurate) {
  MatchVerdict verdict;
  const GroundTruthScore score = match_and_score("scape", "off/mesh000.off", "off/mesh001.off", {}, &verdict);
  EXPECT_TRUE(score.flip_free) << score.flip_rule << "; far " << score.far_fraction;
  EXPECT_LT(score.mean_error, 0.012);
  EXPECT_FALSE(verdict.suspect) << verdict.reasons.at(0);
}

// SCAPE 000 -> 001's refined candidates include maps with a region in the wrong place
// (0.12-0.15 off, measured torn 0.9-2.2%) and the right one (no tear). The right map tears
// nothing; the regional error that tears most is above the verdict's threshold.
TEST_F(RealData, ARegionalErrorTearsTheSurfaceAndTheRightMapDoesNot) {
  const std::string dir = std::string(ISOCORR_SHARED_DATA_DIR) + "/scape";
  const BenchmarkPair pair = listed_pair(dir, "off/mesh000.off", "off/mesh001.off");
  const LoadedMesh s = load_mesh(pair.source_path), t = load_mesh(pair.target_path);
  MeshPairShapes shapes(s.mesh, t.mesh);
  const MatchSettings settings;
  const MatchResult result = run_match(shapes, settings);
  EXPECT_GE(result.quality.torn_share, 0);
  EXPECT_LE(result.quality.torn_share, kTornShare);
  EXPECT_FALSE(result.verdict.suspect);

  const auto source = shapes.shape(ShapeRole::kSource, settings.preprocess, {});
  const auto target = shapes.shape(ShapeRole::kTarget, settings.preprocess, {});
  const GroundTruth truth = load_ground_truth(dir, pair, s.mesh.num_vertices(), t.mesh.num_vertices());
  double most_torn_regional_error = 0;
  for (const DenseCandidate& c : result.diagnostics.refinement.candidates) {
    const double error = score_on_target(t.mesh, c.forward, truth).mean_error;
    std::vector<int> clean_forward(source->mesh().num_vertices());
    for (size_t v = 0; v < clean_forward.size(); ++v)
      clean_forward[v] = target->clean().input_to_clean[c.forward[source->clean().clean_to_input[v]]];
    const double torn = measure_map_tearing(*source, *target, clean_forward).torn_share();
    if (error < 0.05) EXPECT_LE(torn, kTornShare) << "a right candidate, " << error << " off";
    if (error > 0.1 && error < 0.25) most_torn_regional_error = std::max(most_torn_regional_error, torn);
  }
  EXPECT_GT(most_torn_regional_error, kTornShare);
}

// SCAPE 007 -> 009: a whole-body mirror won the dense choice by 2% of its score (0.33
// measured). Decided by both directions' evidence the right map wins (0.026); the choice
// was still a near tie, and the verdict says so.
TEST_F(RealData, ANearTieIsDecidedByBothDirectionsAndSaidSuspect) {
  MatchVerdict verdict;
  const GroundTruthScore score = match_and_score("scape", "off/mesh007.off", "off/mesh009.off", {}, &verdict);
  EXPECT_TRUE(score.flip_free) << score.flip_rule << "; far " << score.far_fraction;
  EXPECT_LT(score.mean_error, 0.035);
  EXPECT_TRUE(verdict.suspect);
  ASSERT_FALSE(verdict.reasons.empty());
  EXPECT_NE(verdict.reasons[0].find("decided by both directions' evidence"), std::string::npos) << verdict.reasons[0];
}

// SCAPE 013 -> 014, the development sets' last wrong map (every refined candidate is off
// by 0.15-0.32): the verdict flags it. Two landmarks a user would click, the top of the head
// and the sole of one foot (the source's highest and lowest vertices, with their true
// partners), turn it right: 0.042 measured.
TEST_F(RealData, TheLastWrongScapePairIsSuspectAndTwoLandmarksTurnItRight) {
  MatchVerdict verdict;
  const GroundTruthScore alone = match_and_score("scape", "off/mesh013.off", "off/mesh014.off", {}, &verdict);
  ASSERT_FALSE(alone.flip_free) << "the pair came out right: pick another wrong one for this test";
  EXPECT_TRUE(verdict.suspect);
  MatchSettings settings;
  settings.landmarks = {{4852, 4852}, {225, 225}};
  const GroundTruthScore helped = match_and_score("scape", "off/mesh013.off", "off/mesh014.off", settings);
  EXPECT_TRUE(helped.flip_free) << helped.flip_rule << "; far " << helped.far_fraction;
  EXPECT_LT(helped.mean_error, 0.05);
}

TEST_F(RealData, Faust5kPairThatC2FMirrorsIsRight) {
  const GroundTruthScore score = match_and_score("faust_5k", "off/tr_reg_000.off", "off/tr_reg_001.off");
  EXPECT_TRUE(score.flip_free) << score.flip_rule << "; mirrored " << score.mirrored_fraction;
  EXPECT_LT(score.mean_error, 0.015);
}

// SCAPE 000 -> 001 without a geodesic ball (the part benchmark's 70% ball, 66% of the area
// kept): the part search's map and the complete pipeline's compete on curvature times the
// cube root of distortion, and the part search's wins: 0.0075 measured, against 0.019 when
// curvature alone chose the complete pipeline's.
TEST_F(RealData, ScapePartWithoutABallIsChosenByCurvatureAndDistortion) {
  const GroundTruthScore score =
      match_part_and_score("scape", "off/mesh000.off", "off/mesh001.off", {CutKind::kGeodesicBall, 0.7, 1, 1});
  EXPECT_TRUE(score.flip_free) << score.flip_rule;
  EXPECT_LT(score.mean_error, 0.012);
}

// A real body with three holes (80% of the area kept: the part benchmark's holes cut),
// matched as a part: 0.013 measured. Before the part's curvature was compared at the whole's
// lengths the choice kept a map with 11% of its points nearer their mirror image (0.048).
TEST_F(RealData, Faust5kPartWithHolesIsRight) {
  const GroundTruthScore score =
      match_part_and_score("faust_5k", "off/tr_reg_000.off", "off/tr_reg_004.off", {CutKind::kHoles, 0.8, 3, 4});
  EXPECT_LT(score.mirrored_fraction, 0.05);
  EXPECT_LT(score.mean_error, 0.025);
}

// A real body that lost a geodesic ball of 46% of its area (the part benchmark's 55% ball):
// 0.024 measured. Chosen among rough candidate maps, a turned body won (0.29, 85% of the
// points nearer their mirror image): the right map covered 0.75 of its share of the target
// and the choice then wanted 0.8. Finished first, the right map agrees far better.
TEST_F(RealData, Faust5kPartWithoutHalfItsAreaIsRight) {
  const GroundTruthScore score = match_part_and_score("faust_5k", "off/tr_reg_000.off", "off/tr_reg_004.off",
                                                      {CutKind::kGeodesicBall, 0.55, 1, 2});
  EXPECT_LT(score.mirrored_fraction, 0.05);
  EXPECT_LT(score.mean_error, 0.05);
}

// A cat's front half (a plane cut keeping 60% of the area): its extremities (nose, ears,
// paws) include tips the whole cat's level-0 samples lack (one sample on its head), so no
// map onto those is consistent (least distortion 0.09) and the search offers finer
// targets: 0.046 measured, against 0.137 with level 0 alone.
TEST_F(RealData, ToscaCatFrontHalfIsRight) {
  const GroundTruthScore score = match_part_and_score("tosca_isometric_5k", "off/cat0.off", "off/cat2.off",
                                                      {CutKind::kPlane, 0.6, 1, 3});
  EXPECT_LT(score.mirrored_fraction, 0.1);
  EXPECT_LT(score.mean_error, 0.08);
}

// The same cut of the 28K-vertex TOSCA cat, not used to choose any setting: its rim samples'
// distances are all upper bounds, and matched anyway they landed half a diameter off and led
// the rest astray (0.21-0.24, over half the points nearer their mirror image); left to the dense
// map, 0.018 measured.
TEST_F(RealData, ToscaHiresCatFrontHalfIsRight) {
  const GroundTruthScore score =
      match_part_and_score("tosca_hires", "off/cat0.off", "off/cat2.off", {CutKind::kPlane, 0.6, 1, 3});
  EXPECT_LT(score.mirrored_fraction, 0.05);
  EXPECT_LT(score.mean_error, 0.04);
}

// The point of `mesh` nearest `p`, among the faces around its nearest vertex and their
// neighbours'.
SurfacePoint nearest_surface_point(const TriangleMesh& mesh, const MeshTopology& topology, const KdTree& vertices,
                                   const Vec3& p) {
  SurfacePoint best;
  double best_distance = 1e300;
  const int nearest = vertices.nearest(p);
  std::vector<int> around = {nearest};
  around.insert(around.end(), topology.neighbours_begin(nearest), topology.neighbours_end(nearest));
  for (const int v : around)
    for (const int* f = topology.faces_begin(v); f != topology.faces_end(v); ++f) {
      const Face& face = mesh.faces[*f];
      const Eigen::Vector3d w = nearest_on_triangle(p, mesh.vertices[face[0]], mesh.vertices[face[1]], mesh.vertices[face[2]]);
      const SurfacePoint candidate{*f, {float(w[0]), float(w[1]), float(w[2])}};
      const double distance = (surface_position(mesh, candidate) - p).squaredNorm();
      if (distance < best_distance) best_distance = distance, best = candidate;
    }
  return best;
}

// FAUST's LPS remesh (10 000 vertices, the first 6890 the registration's) matched to the
// registration of another pose: the 3110 other vertices lie between the target's vertices.
// Their true points are found on the registration of the remesh's own pose (which shares
// its faces with the target's) once the remesh is aligned to it by its first 6890 vertices.
// Measured: mean error 0.0041 of the bounding-box diagonal for the precise map, 0.0077 for
// the vertex map (even the true point's nearest vertex is 0.0067 off).
TEST_F(RealData, PreciseMapIsFinerThanTheVertexMapAcrossResolutions) {
  const std::string data = ISOCORR_SHARED_DATA_DIR;
  const TriangleMesh remesh = load_mesh(data + "/faust_remeshed_lps/off_10000/tr_reg_000.off").mesh;
  const TriangleMesh own_pose = load_mesh(data + "/faust_reg6890/off/tr_reg_000.off").mesh;
  const TriangleMesh target = load_mesh(data + "/faust_reg6890/off/tr_reg_001.off").mesh;
  ASSERT_EQ(own_pose.faces, target.faces);
  constexpr int kRegistration = 6890;
  // The similarity taking the remesh's registration vertices onto its own pose's.
  Eigen::Matrix3Xd from(3, kRegistration), to(3, kRegistration);
  for (int v = 0; v < kRegistration; ++v) from.col(v) = remesh.vertices[v], to.col(v) = own_pose.vertices[v];
  const Eigen::Matrix4d align = Eigen::umeyama(from, to, true);
  const MeshTopology topology(own_pose);
  std::vector<int> ids(own_pose.num_vertices());
  for (int v = 0; v < own_pose.num_vertices(); ++v) ids[v] = v;
  const KdTree vertices(own_pose.vertices, ids);

  const MatchResult result = match_meshes(remesh, target, MatchSettings{});
  Eigen::AlignedBox3d box;
  for (const Vec3& p : target.vertices) box.extend(p);
  const double diagonal = box.diagonal().norm();
  double vertex_error = 0, precise_error = 0;
  for (int v = kRegistration; v < remesh.num_vertices(); ++v) {
    const Vec3 aligned = (align * remesh.vertices[v].homogeneous()).head<3>();
    const Vec3 truth = surface_position(target, nearest_surface_point(own_pose, topology, vertices, aligned));
    vertex_error += (target.vertices[result.output.forward[v]] - truth).norm();
    precise_error += (surface_position(target, result.output.forward_precise[v]) - truth).norm();
  }
  const int extra = remesh.num_vertices() - kRegistration;
  vertex_error /= extra * diagonal;
  precise_error /= extra * diagonal;
  EXPECT_LT(precise_error, 0.75 * vertex_error) << "vertex map " << vertex_error << ", precise map " << precise_error;
  EXPECT_LT(precise_error, 0.006);
}

}  // namespace
}  // namespace isocorr
