// `isocorr match` then `isocorr transfer` on a real FAUST pair, as a user runs them: the
// registrations share their numbering, so what the target carries for its vertex t can be
// made from the source's own vertex t, and the transferred values checked against it.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/textured_mesh.h"
#include "isocorr/output/attribute_files.h"
#include "../client/shell_run.h"

#ifndef ISOCORR_SHARED_DATA_DIR
#define ISOCORR_SHARED_DATA_DIR "../shared/data"
#endif

namespace isocorr {
namespace {

namespace fs = std::filesystem;
using isocorr::testing::run_shell;
using isocorr::testing::ShellRun;

class RealDataTransfer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(ISOCORR_SHARED_DATA_DIR)) return;
    dir_ = new fs::path(fs::temp_directory_path() / ("isocorr_RealDataTransfer_" + std::to_string(getpid())));
    fs::create_directories(*dir_);
    const ShellRun match = cli("match " + source_path() + " " + target_path() + " -o " + file("map.npy") +
                               " --precise-out " + file("precise.npy"));
    matched_ = match.exit_code == 0;
    EXPECT_TRUE(matched_) << match.output;
  }
  static void TearDownTestSuite() {
    if (!dir_) return;
    fs::remove_all(*dir_);
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!dir_) GTEST_SKIP() << "benchmark data not found at " << ISOCORR_SHARED_DATA_DIR;
    ASSERT_TRUE(matched_);
  }

  static ShellRun cli(const std::string& arguments) { return run_shell(std::string(ISOCORR_CLI_PATH) + " " + arguments); }
  static std::string source_path() { return std::string(ISOCORR_SHARED_DATA_DIR) + "/faust_reg6890/off/tr_reg_000.off"; }
  static std::string target_path() { return std::string(ISOCORR_SHARED_DATA_DIR) + "/faust_reg6890/off/tr_reg_001.off"; }
  static std::string file(const std::string& name) { return (*dir_ / name).string(); }

  static double diagonal(const TriangleMesh& mesh) {
    Eigen::AlignedBox3d box;
    for (const Vec3& p : mesh.vertices) box.extend(p);
    return box.diagonal().norm();
  }

  static inline fs::path* dir_ = nullptr;
  static inline bool matched_ = false;
};

// The target carries the source's rest positions; pulled back through the match, each source
// vertex should get its own position. Measured: mean error 0.0024 of the bounding-box diagonal
// through the precise map, 0.0023 through the vertex map.
TEST_F(RealDataTransfer, PositionsComeBackThroughTheMatchedMaps) {
  const TriangleMesh source = load_mesh(source_path()).mesh;
  const std::string csv = file("source_positions.csv");
  {
    std::ofstream out(csv);
    out << "x,y,z\n";
    for (const Vec3& p : source.vertices) out << p.x() << ',' << p.y() << ',' << p.z() << '\n';
  }
  for (const std::string& precise : {std::string(" --precise"), std::string()}) {
    const std::string map = precise.empty() ? file("map.npy") : file("precise.npy");
    const std::string out = file("pulled.npy");
    const ShellRun run = cli("transfer " + source_path() + " " + target_path() + " " + map + precise +
                             " --attribute " + csv + " -o " + out);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const VertexTable pulled = read_vertex_table(out);
    ASSERT_EQ(pulled.rows, source.num_vertices());
    ASSERT_EQ(pulled.columns, 3);
    double error = 0;
    for (int v = 0; v < pulled.rows; ++v)
      error += (Vec3(pulled.values[3 * v], pulled.values[3 * v + 1], pulled.values[3 * v + 2]) - source.vertices[v]).norm();
    error /= pulled.rows * diagonal(source);
    EXPECT_LT(error, 0.006) << (precise.empty() ? "vertex map" : "precise map");
  }
}

// The target textured with a front projection of the source's rest pose (one chart, with a
// material): the source, given the target's UVs, should get the projection of its own
// vertices. Measured: mean UV error 0.0030 of the texture's side.
TEST_F(RealDataTransfer, UvsOfATexturedTargetLandOnTheSource) {
  const TriangleMesh source = load_mesh(source_path()).mesh;
  TexturedMesh target{load_mesh(target_path()).mesh, {}};
  Eigen::AlignedBox3d box;
  for (const Vec3& p : source.vertices) box.extend(p);
  const double side = std::max(box.sizes().x(), box.sizes().y());
  auto projection = [&](const Vec3& p) {
    return std::array<double, 2>{(p.x() - box.min().x()) / side, (p.y() - box.min().y()) / side};
  };
  for (const Vec3& p : source.vertices) target.corners.uvs.push_back(projection(p));
  target.corners.face_uvs = target.mesh.faces;
  target.corners.material_library = "body.mtl";
  target.corners.materials = {"skin"};
  target.corners.face_materials.assign(target.mesh.faces.size(), 0);
  const std::string textured = file("target_textured.obj"), out = file("source_textured.obj");
  write_textured_obj(textured, target);

  const ShellRun run = cli("transfer " + source_path() + " " + textured + " " + file("precise.npy") +
                           " --precise --uv -o " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const TexturedMesh result = load_textured_mesh(out);
  EXPECT_EQ(result.mesh.faces, source.faces);
  EXPECT_EQ(result.corners.material_library, "body.mtl");
  ASSERT_EQ(result.corners.face_uvs.size(), source.faces.size());
  double error = 0;
  for (size_t f = 0; f < source.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto& uv = result.corners.uvs[result.corners.face_uvs[f][k]];
      const auto truth = projection(source.vertices[source.faces[f][k]]);
      error += std::hypot(uv[0] - truth[0], uv[1] - truth[1]);
    }
  error /= 3.0 * source.faces.size();
  EXPECT_LT(error, 0.006);
}

}  // namespace
}  // namespace isocorr
