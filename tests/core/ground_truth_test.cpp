// Parsing of every ground-truth format of shared/data, on small files in a temp folder.
#include "isocorr/eval/ground_truth.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"

#ifndef ISOCORR_SHARED_DATA_DIR
#define ISOCORR_SHARED_DATA_DIR "../shared/data"
#endif

namespace isocorr {
namespace {

namespace fs = std::filesystem;

class GroundTruthFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / (std::string("isocorr_gt_") + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `text` to dir_/relative (creating folders) and returns the path.
  std::string write(const std::string& relative, const std::string& text) {
    const fs::path path = dir_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path.string();
  }
  BenchmarkPair pair(const std::string& source, const std::string& target, const std::string& kind,
                     const std::string& protocol = "") {
    return {(dir_ / source).string(), (dir_ / target).string(), kind, protocol};
  }
  // Expects InputError whose message contains every fragment.
  template <typename F>
  void expect_input_error(F&& call, std::initializer_list<std::string> fragments) {
    try {
      call();
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      for (const std::string& f : fragments) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }

  fs::path dir_;
  std::string ds() const { return dir_.string(); }
};

TEST_F(GroundTruthFiles, PairsTsvSkipsBlankLinesAndResolvesPaths) {
  write("pairs.tsv", "source\ttarget\tgt_kind\tprotocol\n\noff/a.off\toff/b.off\tvts\tp1\r\n\n"
                     "off/a.off\t../other/off/c.off\tindex_map:gt/a_to_c.txt\tpartial\n");
  const auto pairs = read_pairs_tsv(ds());
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].source_path, ds() + "/off/a.off");
  EXPECT_EQ(pairs[0].target_path, ds() + "/off/b.off");
  EXPECT_EQ(pairs[0].gt_kind, "vts");
  EXPECT_EQ(pairs[0].protocol, "p1");
  EXPECT_EQ(pairs[1].target_path, ds() + "/../other/off/c.off");
  EXPECT_EQ(pairs[1].gt_kind, "index_map:gt/a_to_c.txt");
}

TEST_F(GroundTruthFiles, PairsTsvRejectsMissingHeaderAndShortLines) {
  write("pairs.tsv", "off/a.off\toff/b.off\tvts\tp\n");
  expect_input_error([&] { read_pairs_tsv(ds()); }, {"pairs.tsv:1"});
  write("pairs.tsv", "source\ttarget\tgt_kind\tprotocol\noff/a.off off/b.off\n");
  expect_input_error([&] { read_pairs_tsv(ds()); }, {"pairs.tsv:2"});
}

TEST_F(GroundTruthFiles, IdentityWithToscaSymmetry) {
  write("gt/symmetry/cat.sym", "2\n1\n3\n5\n4\n");  // 1-based
  const GroundTruth gt = load_ground_truth(ds(), pair("off/cat0.off", "off/cat1.off", "identity"), 5, 5);
  EXPECT_EQ(gt.source, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(gt.target, gt.source);
  EXPECT_EQ(gt.mirrored_target, (std::vector<int>{1, 0, 2, 4, 3}));
  EXPECT_NE(gt.description.find("cat.sym"), std::string::npos);
}

// Vertex i to vertex i means nothing between meshes of different vertex counts.
TEST_F(GroundTruthFiles, IdentityNeedsEqualVertexCounts) {
  expect_input_error([&] { load_ground_truth(ds(), pair("off/cat0.off", "off/cat1.off", "identity"), 6, 5); },
                     {"identity", "6", "5"});
}

TEST_F(GroundTruthFiles, IdentityWithKidsFloatSymmetryAndWithout) {
  write("gt/sym.txt", "   2.0000000e+00   1.0000000e+00   3.0000000e+00\n");
  GroundTruth gt = load_ground_truth(ds(), pair("off/0001.null.0.off", "off/0001.isometry.1.off", "identity"), 3, 3);
  EXPECT_EQ(gt.mirrored_target, (std::vector<int>{1, 0, 2}));
  fs::remove(dir_ / "gt/sym.txt");
  gt = load_ground_truth(ds(), pair("off/mesh000.off", "off/mesh001.off", "identity"), 4, 4);
  EXPECT_EQ(gt.target.size(), 4u);
  EXPECT_TRUE(gt.mirrored_target.empty());
}

TEST_F(GroundTruthFiles, BadSymmetryIndex) {
  write("gt/symmetry/cat.sym", "2\n1\n9\n");
  expect_input_error([&] { load_ground_truth(ds(), pair("off/cat0.off", "off/cat1.off", "identity"), 3, 3); },
                     {"cat.sym:3", "9"});
}

TEST_F(GroundTruthFiles, VtsOneBasedWithSymmetricFile) {
  write("corres/a.vts", "1\n3\n3\n");
  write("corres/b.vts", "2\n4\n1\n");
  write("corres/b.sym.vts", "4\n2\n1\n");
  const GroundTruth gt = load_ground_truth(ds(), pair("off/a.off", "off/b.off", "vts"), 3, 4);
  EXPECT_EQ(gt.source, (std::vector<int>{0, 2, 2}));
  EXPECT_EQ(gt.target, (std::vector<int>{1, 3, 0}));
  EXPECT_EQ(gt.mirrored_target, (std::vector<int>{3, 1, 0}));
}

TEST_F(GroundTruthFiles, VtsBadIndexNamesFileAndLine) {
  write("corres/a.vts", "1\n2\n");
  write("corres/b.vts", "1\n5\n");
  expect_input_error([&] { load_ground_truth(ds(), pair("off/a.off", "off/b.off", "vts"), 2, 4); }, {"b.vts:2"});
  write("corres/b.vts", "0\n1\n");  // 0 is not a 1-based index
  expect_input_error([&] { load_ground_truth(ds(), pair("off/a.off", "off/b.off", "vts"), 2, 4); }, {"b.vts:1"});
}

TEST_F(GroundTruthFiles, Prefix6890) {
  const GroundTruth gt = load_ground_truth(ds(), pair("off/a.off", "off/b.off", "prefix6890"), 10000, 6890);
  ASSERT_EQ(gt.source.size(), 6890u);
  EXPECT_EQ(gt.target.back(), 6889);
  EXPECT_THROW(load_ground_truth(ds(), pair("off/a.off", "off/b.off", "prefix6890"), 5000, 6890), InputError);
}

TEST_F(GroundTruthFiles, RefToNullWithNullSymmetryInBothLayouts) {
  write("gt/kid01_ref.txt", "     1      3 \n     2      2 \n     3      1 \n");
  write("gt/kid00_sym.txt", "     2 \n     1 \n     0 \n");  // one column, 0 = no mirror
  GroundTruth gt = load_ground_truth(ds(), pair("off/kid01.off", "off/kid00.off", "ref_to_null"), 3, 3);
  EXPECT_EQ(gt.source, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(gt.target, (std::vector<int>{2, 1, 0}));
  EXPECT_EQ(gt.mirrored_target, (std::vector<int>{-1, 0, 1}));
  write("gt/kid00_sym.txt", "1 2\n2 1\n3 0\n");  // `i j` lines
  gt = load_ground_truth(ds(), pair("off/kid01.off", "off/kid00.off", "ref_to_null"), 3, 3);
  EXPECT_EQ(gt.mirrored_target, (std::vector<int>{-1, 0, 1}));
  write("gt/kid01_ref.txt", "1 3\n2 4\n");
  expect_input_error([&] { load_ground_truth(ds(), pair("off/kid01.off", "off/kid00.off", "ref_to_null"), 3, 3); },
                     {"kid01_ref.txt:2"});
}

TEST_F(GroundTruthFiles, SparseVtsSkipsMissingAndSwapsFeatures) {
  write("gt/1.vts", "  5 0.1 0.2 0.3\n  6 0 0 0\n  7 0 0 0\n -1 0 0 0\n");
  write("gt/2.vts", "  0 0.1 0.2 0.3\n  1 0 0 0\n  2 0 0 0\n  3 0 0 0\n");
  write("gt/1.sym.info", "0 1\n\n2\n");
  const GroundTruth gt =
      load_ground_truth(ds(), pair("off/1.off", "off/2.off", "sparse_vts", "class1_Human_all_pairs"), 8, 4);
  EXPECT_EQ(gt.source, (std::vector<int>{5, 6, 7}));
  EXPECT_EQ(gt.target, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(gt.mirrored_target, (std::vector<int>{1, 0, 2}));
  // Without a class in the protocol there is no symmetry.
  EXPECT_TRUE(load_ground_truth(ds(), pair("off/1.off", "off/2.off", "sparse_vts"), 8, 4).mirrored_target.empty());
  expect_input_error([&] { load_ground_truth(ds(), pair("off/1.off", "off/2.off", "sparse_vts"), 7, 4); },
                     {"1.vts:3"});
}

TEST_F(GroundTruthFiles, IndexMapToToscaMeshUsesItsSymmetry) {
  write("partial/gt/p_to_cat2.txt", "2\n-1\n0\n");
  write("tosca/gt/symmetry/cat.sym", "2\n1\n4\n3\n");
  const std::string partial = (dir_ / "partial").string();
  BenchmarkPair p{partial + "/off/cat11.off", partial + "/../tosca/off/cat2.off", "index_map:gt/p_to_cat2.txt", ""};
  GroundTruth gt = load_ground_truth(partial, p, 3, 4);
  EXPECT_EQ(gt.source, (std::vector<int>{0, 2}));
  EXPECT_EQ(gt.target, (std::vector<int>{2, 0}));
  EXPECT_EQ(gt.mirrored_target, (std::vector<int>{3, 1}));
  p.target_path = partial + "/../scape/off/mesh000.off";
  EXPECT_TRUE(load_ground_truth(partial, p, 3, 4).mirrored_target.empty());
  expect_input_error([&] { load_ground_truth(partial, p, 3, 2); }, {"p_to_cat2.txt:1"});
  expect_input_error([&] { load_ground_truth(partial, p, 4, 4); }, {"p_to_cat2.txt"});  // line count
}

TEST_F(GroundTruthFiles, UnknownKindAndMissingFile) {
  EXPECT_THROW(load_ground_truth(ds(), pair("off/a.off", "off/b.off", "bogus"), 3, 3), InputError);
  expect_input_error([&] { load_ground_truth(ds(), pair("off/a.off", "off/b.off", "vts"), 3, 3); }, {"a.vts"});
}

TEST(GroundTruthRealData, ToscaIsometricCat0ToCat1) {
  const std::string dataset = std::string(ISOCORR_SHARED_DATA_DIR) + "/tosca_isometric_5k";
  if (!fs::is_regular_file(dataset + "/pairs.tsv"))
    GTEST_SKIP() << "shared data not found at " << dataset << " (set ISOCORR_SHARED_DATA_DIR)";
  BenchmarkPair cat{};
  for (const BenchmarkPair& p : read_pairs_tsv(dataset))
    if (p.source_path == dataset + "/off/cat0.off" && p.target_path == dataset + "/off/cat1.off") cat = p;
  ASSERT_EQ(cat.gt_kind, "vts") << "cat0 -> cat1 not listed in pairs.tsv";
  const int ns = load_mesh(cat.source_path).mesh.num_vertices();
  const int nt = load_mesh(cat.target_path).mesh.num_vertices();
  const GroundTruth gt = load_ground_truth(dataset, cat, ns, nt);
  ASSERT_EQ(gt.source.size(), 5000u);
  ASSERT_EQ(gt.target.size(), 5000u);
  ASSERT_EQ(gt.mirrored_target.size(), 5000u);
  for (size_t k = 0; k < gt.source.size(); ++k) {
    ASSERT_TRUE(gt.source[k] >= 0 && gt.source[k] < ns);
    ASSERT_TRUE(gt.target[k] >= 0 && gt.target[k] < nt);
    ASSERT_TRUE(gt.mirrored_target[k] >= 0 && gt.mirrored_target[k] < nt);
  }
}

}  // namespace
}  // namespace isocorr
