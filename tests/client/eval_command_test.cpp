// `isocorr eval SOURCE TARGET MAP` as a user runs it, on the generated example pair and its
// known map, with and without a dataset folder.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "example_dataset.h"

namespace isocorr {
namespace {

using isocorr::testing::run_shell;
using isocorr::testing::ShellRun;

class EvalCommand : public testing::ExampleDatasetTest<3> {
 protected:
  static ShellRun eval(const std::string& arguments) {
    return run_shell(std::string(ISOCORR_CLI_PATH) + " eval " + arguments);
  }
  static nlohmann::json json_of(const ShellRun& run) {
    return nlohmann::json::parse(run.output.substr(run.output.find('{')));
  }
};

TEST_F(EvalCommand, ScoresTheKnownMapWithAndWithoutADatasetFolder) {
  // Relative meshes start in the dataset folder, whose pairs.tsv names the ground truth.
  const ShellRun in_dataset = eval("meshes/creature.ply meshes/creature_moved.ply " +
                                   path("gt/creature_to_moved.txt") + " --dataset " + dir_->string() + " --json");
  ASSERT_EQ(in_dataset.exit_code, 0) << in_dataset.output;
  const nlohmann::json score = json_of(in_dataset);
  EXPECT_LT(score["d_grd"].get<double>(), 1e-9);
  EXPECT_TRUE(score["flip_free"].get<bool>());

  const ShellRun alone = eval(path("meshes/creature.ply") + " " + path("meshes/creature_moved.ply") + " " +
                              path("gt/creature_to_moved.txt") + " --gt-kind index_map:" +
                              path("gt/creature_to_moved.txt") + " --json");
  ASSERT_EQ(alone.exit_code, 0) << alone.output;
  EXPECT_EQ(json_of(alone)["d_grd"], score["d_grd"]);
}

// The map first, as eval and render once took it, is refused before anything is read.
TEST_F(EvalCommand, TheMapFirstIsExitCodeTwoNamingTheOrder) {
  const ShellRun map_first = eval(path("gt/creature_to_moved.txt") + " meshes/creature.ply meshes/creature_moved.ply"
                                  " --dataset " + dir_->string());
  EXPECT_EQ(map_first.exit_code, 2);
  EXPECT_NE(map_first.output.find("`isocorr eval SOURCE TARGET MAP`"), std::string::npos) << map_first.output;
  EXPECT_EQ(map_first.output.find("D_grd"), std::string::npos) << map_first.output;

  const ShellRun old_flags = eval(path("gt/creature_to_moved.txt") + " --dataset " + dir_->string() +
                                  " --source meshes/creature.ply --target meshes/creature_moved.ply");
  EXPECT_EQ(old_flags.exit_code, 2);
  EXPECT_NE(old_flags.output.find("--source is gone, the meshes are positional: `isocorr eval SOURCE TARGET MAP`"), std::string::npos)
      << old_flags.output;
}

}  // namespace
}  // namespace isocorr
