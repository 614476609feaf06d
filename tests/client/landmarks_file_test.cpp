// `--landmarks FILE`: the file's format, refusals that name the file and the line, and a
// match through the real binary that honours and reports the landmarks.
#include "landmarks_file.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "example_dataset.h"
#include "isocorr/util/error.h"

namespace isocorr::cli {
namespace {

namespace fs = std::filesystem;
using isocorr::testing::run_shell;
using isocorr::testing::ShellRun;

class LandmarksFileTest : public isocorr::testing::ExampleDatasetTest<3> {
 protected:
  static std::string write(const std::string& name, const std::string& text) {
    const std::string file = path(name);
    std::ofstream(file) << text;
    return file;
  }
  static std::string refusal(const std::string& file) {
    std::vector<Landmark> landmarks;
    LandmarksFile where;
    try {
      read_landmarks_file(file, landmarks, where);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  // The ground truth's image of source vertex v (isocorr-make-examples writes one per line).
  static int truth(int v) {
    std::ifstream in(path("gt/creature_to_moved.txt"));
    int image = -1;
    for (int i = 0; i <= v; ++i) in >> image;
    return image;
  }
};

TEST_F(LandmarksFileTest, ReadsPairsCommentsAndBlankLines) {
  const std::string file = write("good.txt", "# nose, then a hand\n12 40\n\n  7\t9   # hand\n");
  std::vector<Landmark> landmarks = {{1, 1}};
  LandmarksFile where;
  read_landmarks_file(file, landmarks, where);
  EXPECT_EQ(landmarks, (std::vector<Landmark>{{12, 40}, {7, 9}}));
  EXPECT_EQ(where.lines, (std::vector<int>{2, 4}));
  EXPECT_NO_THROW(check_landmarks_fit(where, landmarks, 13, 41));
  try {
    check_landmarks_fit(where, landmarks, 13, 40);
    ADD_FAILURE() << "out of range accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "landmarks file '" + file +
                                         "' line 2: target vertex 40 is out of range: the target mesh has 40 vertices");
  }
}

TEST_F(LandmarksFileTest, RefusalsNameTheFileAndTheLine) {
  const std::string duplicate = write("duplicate.txt", "1 2\n# comment\n3 4\n1 2\n");
  EXPECT_EQ(refusal(duplicate), "landmarks file '" + duplicate + "' line 4: the pair 1 2 is given twice (line 1)");
  const std::string two_targets = write("two_targets.txt", "1 2\n1 5\n");
  EXPECT_EQ(refusal(two_targets),
            "landmarks file '" + two_targets + "' line 2: source vertex 1 is given two targets, 2 and 5 (line 1)");
  const std::string two_sources = write("two_sources.txt", "1 2\n\n6 2\n");
  EXPECT_NE(refusal(two_sources).find("line 3: target vertex 2 is given two sources"), std::string::npos);
  for (const char* malformed : {"1\n", "1 2 3\n", "a b\n", "1 2.5\n", "1 99999999999\n"}) {
    const std::string file = write("malformed.txt", std::string("0 0\n") + malformed);
    EXPECT_NE(refusal(file).find("line 2: expected 'source_vertex target_vertex'"), std::string::npos) << malformed;
  }
  EXPECT_NE(refusal(path("missing.txt")).find("cannot be read"), std::string::npos);
}

TEST_F(LandmarksFileTest, TheMatchCommandTakesThemAndRefusesBadOnes) {
  const std::string cli = ISOCORR_CLI_PATH;
  const std::string meshes = " " + path("meshes/creature.ply") + " " + path("meshes/creature_moved.ply");
  const std::string good = write("truth.txt", "0 " + std::to_string(truth(0)) + "\n100 " + std::to_string(truth(100)) + "\n");
  const std::string report = path("report.json");
  const ShellRun match =
      run_shell(cli + " match" + meshes + " -o " + path("out.map") + " --report " + report + " --landmarks " + good);
  ASSERT_EQ(match.exit_code, 0) << match.output;
  std::ifstream in(report);
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_EQ(json["settings"]["landmarks"].size(), 2u);
  EXPECT_EQ(json["landmarks"]["count"], 2);
  EXPECT_EQ(json["landmarks"]["chosen_map_honours_them"], true);

  const std::string beyond = write("beyond.txt", "0 0\n# the source has fewer vertices\n100000 1\n");
  const ShellRun refused = run_shell(cli + " match" + meshes + " -o " + path("never.map") + " --landmarks " + beyond);
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.output.find("landmarks file '" + beyond + "' line 3: source vertex 100000 is out of range"),
            std::string::npos)
      << refused.output;
  EXPECT_FALSE(fs::exists(path("never.map")));

  const std::string contradictory = write("contradictory.txt", "0 0\n0 1\n");
  const ShellRun contradiction =
      run_shell(cli + " match" + meshes + " -o " + path("never.map") + " --landmarks " + contradictory);
  EXPECT_EQ(contradiction.exit_code, 2);
  EXPECT_NE(contradiction.output.find("line 2: source vertex 0 is given two targets"), std::string::npos)
      << contradiction.output;
}

}  // namespace
}  // namespace isocorr::cli
