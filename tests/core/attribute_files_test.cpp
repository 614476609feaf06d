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

}  // namespace
}  // namespace isocorr
