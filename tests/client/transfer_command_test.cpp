// `isocorr transfer` and precise maps from `isocorr match --precise-out`, as a user runs
// them on the generated example pair and its known map.
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "example_dataset.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/textured_mesh.h"
#include "isocorr/output/attribute_files.h"
#include "isocorr/output/map_files.h"

namespace isocorr {
namespace {

using isocorr::testing::run_shell;
using isocorr::testing::ShellRun;

class TransferCommand : public testing::ExampleDatasetTest<3> {
 protected:
  static ShellRun cli(const std::string& arguments) { return run_shell(std::string(ISOCORR_CLI_PATH) + " " + arguments); }
  static std::string meshes() { return path("meshes/creature.ply") + " " + path("meshes/creature_moved.ply") + " "; }
  // The target's vertex positions as a CSV table with a header.
  static std::string target_positions_csv() {
    const std::string csv = path("positions.csv");
    std::ofstream out(csv);
    out << "x,y,z\n";
    for (const Vec3& p : load_mesh(path("meshes/creature_moved.ply")).mesh.vertices)
      out << p.x() << ',' << p.y() << ',' << p.z() << '\n';
    return csv;
  }
};

TEST_F(TransferCommand, CarriesTheTargetsRowsThroughTheKnownMap) {
  const std::string csv = target_positions_csv(), out = path("pulled.npy");
  const ShellRun run = cli("transfer " + meshes() + path("gt/creature_to_moved.txt") + " --attribute " + csv + " -o " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const VertexTable pulled = read_vertex_table(out);
  const VertexTable target = read_vertex_table(csv);
  const std::vector<int> truth = read_map(path("gt/creature_to_moved.txt"));
  ASSERT_EQ(pulled.rows, static_cast<int>(truth.size()));
  ASSERT_EQ(pulled.columns, 3);
  for (size_t v = 0; v < truth.size(); ++v)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(pulled.values[v * 3 + c], target.values[truth[v] * 3 + c]);
}

TEST_F(TransferCommand, PreciseMapsFromMatchAreScoredAndInterpolated) {
  const std::string precise = path("precise.txt"), reverse_precise = path("reverse_precise.npy");
  const ShellRun match = cli("match " + meshes() + "-o " + path("map.txt") + " --precise-out " + precise +
                             " --reverse-precise-out " + reverse_precise);
  ASSERT_EQ(match.exit_code, 0) << match.output;
  const ShellRun eval = cli("eval " + meshes() + precise + " --precise --json --gt-kind index_map:" +
                            path("gt/creature_to_moved.txt"));
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  EXPECT_LT(nlohmann::json::parse(eval.output.substr(eval.output.find('{')))["d_grd"].get<double>(), 1e-4);

  // The pair is an exact copy: every point sits on its true vertex.
  const std::string out = path("pulled.txt");
  const ShellRun run = cli("transfer " + meshes() + precise + " --precise --attribute " + target_positions_csv() + " -o " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const VertexTable pulled = read_vertex_table(out);
  const TriangleMesh target = load_mesh(path("meshes/creature_moved.ply")).mesh;
  const std::vector<int> truth = read_map(path("gt/creature_to_moved.txt"));
  for (size_t v = 0; v < truth.size(); ++v)
    EXPECT_LT((Vec3(pulled.values[v * 3], pulled.values[v * 3 + 1], pulled.values[v * 3 + 2]) - target.vertices[truth[v]]).norm(),
              1e-4);
}

TEST_F(TransferCommand, LabelsAndColouredPly) {
  const std::string labels = path("labels.txt");
  {
    std::ofstream out(labels);
    for (int v = 0; v < load_mesh(path("meshes/creature_moved.ply")).mesh.num_vertices(); ++v) out << v % 3 << '\n';
  }
  const ShellRun run = cli("transfer " + meshes() + path("gt/creature_to_moved.txt") + " --labels --attribute " +
                           labels + " -o " + path("pulled_labels.txt"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<int> truth = read_map(path("gt/creature_to_moved.txt"));
  std::ifstream pulled(path("pulled_labels.txt"));
  for (size_t v = 0; v < truth.size(); ++v) {
    int label = -5;
    pulled >> label;
    EXPECT_EQ(label, truth[v] % 3);
  }
  const ShellRun ply = cli("transfer " + meshes() + path("gt/creature_to_moved.txt") + " --attribute " +
                           target_positions_csv() + " -o " + path("coloured.ply"));
  ASSERT_EQ(ply.exit_code, 0) << ply.output;
  EXPECT_EQ(load_mesh(path("coloured.ply")).mesh.num_vertices(), static_cast<int>(truth.size()));
}

// `mesh` as an OBJ whose UVs are its vertices' x and y, with a material library.
TexturedMesh textured_target(const std::string& mesh, const std::string& obj) {
  TexturedMesh textured{load_mesh(mesh).mesh, {}};
  for (const Vec3& p : textured.mesh.vertices) textured.corners.uvs.push_back({p.x(), p.y()});
  textured.corners.face_uvs = textured.mesh.faces;
  textured.corners.material_library = "skin.mtl";
  textured.corners.materials = {"skin"};
  textured.corners.face_materials.assign(textured.mesh.faces.size(), 0);
  write_textured_obj(obj, textured);
  return textured;
}

TEST_F(TransferCommand, UvsAndMaterialsOfATexturedTarget) {
  const std::string obj = path("textured.obj"), out = path("source_textured.obj");
  const TexturedMesh target = textured_target(path("meshes/creature_moved.ply"), obj);
  const ShellRun run = cli("transfer " + path("meshes/creature.ply") + " " + obj + " " + path("gt/creature_to_moved.txt") +
                           " --uv -o " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const TexturedMesh source = load_textured_mesh(out);
  const std::vector<int> truth = read_map(path("gt/creature_to_moved.txt"));
  EXPECT_EQ(source.corners.material_library, "skin.mtl");
  ASSERT_EQ(source.corners.face_uvs.size(), source.mesh.faces.size());
  for (size_t f = 0; f < source.mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto& uv = source.corners.uvs[source.corners.face_uvs[f][k]];
      const auto& expected = target.corners.uvs[truth[source.mesh.faces[f][k]]];
      EXPECT_NEAR(uv[0], expected[0], 1e-6);
      EXPECT_NEAR(uv[1], expected[1], 1e-6);
    }
  const ShellRun neither = cli("transfer " + path("meshes/creature.ply") + " " + obj + " " +
                               path("gt/creature_to_moved.txt") + " -o " + out);
  EXPECT_EQ(neither.exit_code, 2);
  EXPECT_NE(neither.output.find("give either --attribute FILE or --uv"), std::string::npos) << neither.output;
}

TEST_F(TransferCommand, ATableOfTheWrongLengthIsExitCodeTwoNamingTheFile) {
  const std::string short_table = path("short.txt");
  std::ofstream(short_table) << "1\n2\n3\n";
  const ShellRun run = cli("transfer " + meshes() + path("gt/creature_to_moved.txt") + " --attribute " + short_table +
                           " -o " + path("out.txt"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find("short.txt: 3 rows for a target of"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace isocorr
