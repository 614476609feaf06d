// Attribute tables read from text, CSV and .npy, and written back.
#include "isocorr/output/attribute_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

namespace fs = std::filesystem;

class AttributeFiles : public ::testing::Test {
 protected:
  fs::path dir_ = fs::temp_directory_path() / ("isocorr-attributes-" + std::to_string(::getpid()));
  void SetUp() override { fs::create_directories(dir_); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write_text(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
};

TEST_F(AttributeFiles, CsvWithAHeaderAndComments) {
  const VertexTable table = read_vertex_table(write_text("c.csv", "red,green,blue\n# a comment\n1,0,0\n0,0.5,1\n"));
  EXPECT_EQ(table.rows, 2);
  EXPECT_EQ(table.columns, 3);
  EXPECT_EQ(table.values, (std::vector<double>{1, 0, 0, 0, 0.5, 1}));
}

TEST_F(AttributeFiles, RowsOfDifferentLengthsNameTheLine) {
  try {
    read_vertex_table(write_text("bad.txt", "1 2\n3 4\n5\n"));
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt:3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_vertex_table(write_text("word.txt", "1 2\n3 x\n")), InputError);
  EXPECT_THROW(read_vertex_table(write_text("empty.txt", "# nothing\n")), InputError);
}

TEST_F(AttributeFiles, NpyTablesRoundTripAndLabelsMustBeWhole) {
  const VertexTable table = {3, 2, {0.5, 1, 2, 3, 4, 5}};
  const std::string path = (dir_ / "t.npy").string();
  write_vertex_table(path, table);
  const VertexTable back = read_vertex_table(path);
  EXPECT_EQ(back.rows, 3);
  EXPECT_EQ(back.columns, 2);
  EXPECT_EQ(back.values, table.values);
  EXPECT_EQ(labels_of({3, 1, {1, -2, 40}}, "l"), (std::vector<int64_t>{1, -2, 40}));
  EXPECT_THROW(labels_of({2, 1, {1, 0.5}}, "l"), InputError);
  EXPECT_THROW(labels_of(table, "l"), InputError);
}

TEST_F(AttributeFiles, PlyVertexColoursAndNamedProperties) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.faces = {{0, 1, 2}};
  const std::string coloured = (dir_ / "coloured.ply").string();
  write_coloured_ply(coloured, mesh, {3, 3, {255, 0, 0, 0, 255, 0, 0, 0, 128}});
  const VertexTable colours = read_vertex_table(coloured);
  EXPECT_EQ(colours.rows, 3);
  EXPECT_EQ(colours.values, (std::vector<double>{255, 0, 0, 0, 255, 0, 0, 0, 128}));

  const std::string weighted = write_text("weighted.ply",
                                          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                          "property float z\nproperty float weight\nelement face 1\n"
                                          "property list uchar int vertex_indices\nend_header\n"
                                          "0 0 0 0.25\n1 0 0 0.5\n0 1 0 1\n3 0 1 2\n");
  const VertexTable weights = read_vertex_table(weighted, {"weight"});
  EXPECT_EQ(weights.columns, 1);
  EXPECT_EQ(weights.values, (std::vector<double>{0.25, 0.5, 1}));
  try {
    read_vertex_table(weighted);  // no colours in it
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no scalar property 'red' (it has: x y z weight)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace isocorr
