// The `isocorr` binary as a user runs it: exit codes, map files, report, bad input.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "isocorr/version.h"
#include "example_dataset.h"

namespace {

namespace fs = std::filesystem;

using isocorr::testing::run_shell;
using isocorr::testing::ShellRun;

std::vector<int> read_lines(const fs::path& path) {
  std::vector<int> values;
  std::ifstream in(path);
  for (int v; in >> v;) values.push_back(v);
  return values;
}

class MatchCommand : public isocorr::testing::ExampleDatasetTest<3> {
 protected:
  const std::string cli_ = ISOCORR_CLI_PATH;
};

TEST_F(MatchCommand, WritesMapsAndReportThatEvalScores) {
  const fs::path map = *dir_ / "out.map", reverse = *dir_ / "out.reverse.map", report = *dir_ / "report.json";
  const ShellRun match = run_shell(cli_ + " match " + (*dir_ / "meshes/creature.ply").string() + " " +
                        (*dir_ / "meshes/creature_moved.ply").string() + " -o " + map.string() +
                        " --reverse-out " + reverse.string() + " --report " + report.string() +
                        " --colour-ply " + (*dir_ / "view_").string());
  ASSERT_EQ(match.exit_code, 0) << match.output;
  EXPECT_GT(fs::file_size(*dir_ / "view_source.ply"), 0u);
  EXPECT_EQ(fs::file_size(*dir_ / "view_target.ply"), fs::file_size(*dir_ / "view_source.ply"));
  const std::vector<int> forward = read_lines(map);
  const std::vector<int> truth = read_lines(*dir_ / "gt/creature_to_moved.txt");
  ASSERT_EQ(forward.size(), truth.size());
  ASSERT_EQ(read_lines(reverse).size(), truth.size());
  int exact = 0;
  for (size_t i = 0; i < truth.size(); ++i) exact += forward[i] == truth[i];
  EXPECT_GE(exact, 0.99 * truth.size());
  // The last line says whether the result may be wrong; an exact copy is a clear choice.
  const std::string last_line = match.output.substr(match.output.rfind('\n', match.output.size() - 2) + 1);
  EXPECT_NE(last_line.find("verdict: ok"), std::string::npos) << last_line;

  std::ifstream in(report);
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_EQ(json["verdict"]["status"], "ok");
  EXPECT_EQ(json["verdict"]["reasons"], nlohmann::json::array());
  EXPECT_GT(json["timings_seconds"]["total"].get<double>(), 0);
  // The refine stage's steps are listed apart, every one of them, and fit within it.
  double steps = 0;
  for (const char* step : {"screen", "refine", "drop_duplicates", "preselect", "finish", "choose", "unfold_mirrors",
                           "spectral_polish", "curvature_polish", "finish_with_mirror_repair", "refine_again",
                           "final_polish"}) {
    ASSERT_TRUE(json["refine_steps_seconds"].contains(step)) << step;
    steps += json["refine_steps_seconds"][step].get<double>();
  }
  EXPECT_LE(steps, json["timings_seconds"]["refine"].get<double>() + 1e-6);
  EXPECT_FALSE(json["tracked"].empty());
  EXPECT_LT(json["final"]["diso"].get<double>(), 0.01);

  // The report says what made it: the version and both inputs with their digests.
  EXPECT_EQ(json["version"], isocorr::kVersion);
  EXPECT_EQ(json["inputs"]["source"]["file"], (*dir_ / "meshes/creature.ply").string());
  EXPECT_EQ(json["inputs"]["target"]["sha256"].get<std::string>().size(), 64u);
  // The last line gives the report's choice and final orientation.
  char orientation[16];
  std::snprintf(orientation, sizeof orientation, "%.2f", json["final"]["orientation"].get<double>());
  EXPECT_NE(match.output.find("orientation " + std::string(orientation)), std::string::npos) << match.output;
  EXPECT_NE(match.output.find("chose tracked map " + std::to_string(json["chosen"].get<int>()) + " "), std::string::npos)
      << match.output;

  const ShellRun eval = run_shell(cli_ + " eval meshes/creature.ply meshes/creature_moved.ply " + map.string() +
                                  " --dataset " + dir_->string() + " --json");
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  const nlohmann::json score = nlohmann::json::parse(eval.output.substr(eval.output.find('{')));
  EXPECT_TRUE(score["flip_free"].get<bool>());
  EXPECT_LT(score["d_grd"].get<double>(), 0.01);
}

// A map that could not be written is said before the match runs, naming the directory.
TEST_F(MatchCommand, OutputIntoAMissingDirectoryIsRefusedBeforeTheMatch) {
  const ShellRun match = run_shell(cli_ + " match " + (*dir_ / "meshes/creature.ply").string() + " " +
                                   (*dir_ / "meshes/creature_moved.ply").string() + " -o /nonexistent/dir/x.map");
  EXPECT_EQ(match.exit_code, 2);
  EXPECT_NE(match.output.find("'/nonexistent/dir'"), std::string::npos) << match.output;
  EXPECT_EQ(match.output.find("stage"), std::string::npos) << match.output;  // no match ran
}

TEST_F(MatchCommand, VersionAndLocalCommandsFirstInHelp) {
  const ShellRun version = run_shell(cli_ + " --version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_NE(version.output.find(std::string("isocorr ") + isocorr::kVersion), std::string::npos) << version.output;
  const ShellRun help = run_shell(cli_ + " --help");
  EXPECT_EQ(help.exit_code, 0);
  const size_t match = help.output.find("  match"), upload = help.output.find("  upload");
  ASSERT_NE(match, std::string::npos) << help.output;
  if (upload != std::string::npos) EXPECT_LT(match, upload) << help.output;
}

TEST_F(MatchCommand, CutPartMatchesWithPartialAndItsReverseMapMarksTheRest) {
  const fs::path part = *dir_ / "meshes/part.ply", index_map = *dir_ / "part_to_creature.txt";
  const ShellRun cut = run_shell(cli_ + " cut " + (*dir_ / "meshes/creature.ply").string() + " -o " + part.string() +
                                 " --index-map " + index_map.string() + " --cut ball --keep 0.9 --seed 3");
  ASSERT_EQ(cut.exit_code, 0) << cut.output;
  // The part's ground truth on the moved creature: its index map composed with the pair's.
  const std::vector<int> part_to_full = read_lines(index_map), full_to_moved = read_lines(*dir_ / "gt/creature_to_moved.txt");
  {
    std::ofstream gt(*dir_ / "gt/part_to_moved.txt");
    for (int v : part_to_full) gt << full_to_moved.at(v) << '\n';
  }

  const fs::path map = *dir_ / "part.map", reverse = *dir_ / "part.reverse.map", report = *dir_ / "part.json";
  const ShellRun match = run_shell(cli_ + " match " + part.string() + " " + (*dir_ / "meshes/creature_moved.ply").string() +
                                   " --partial -o " + map.string() + " --reverse-out " + reverse.string() +
                                   " --report " + report.string());
  ASSERT_EQ(match.exit_code, 0) << match.output;
  EXPECT_NE(match.output.find("of the target's area matched"), std::string::npos) << match.output;
  const std::vector<int> back = read_lines(reverse);
  ASSERT_EQ(back.size(), full_to_moved.size());
  const long unmatched = std::count(back.begin(), back.end(), -1);
  EXPECT_GT(unmatched, 0.02 * back.size());
  EXPECT_LT(unmatched, 0.3 * back.size());
  std::ifstream in(report);
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_EQ(json["settings"]["method"], "part");
  EXPECT_NEAR(json["part"]["target_matched_share"].get<double>(), 0.9, 0.1);
  // The part search's candidates are listed with the evidence it weighed.
  ASSERT_FALSE(json["part"]["search_candidates"].empty());
  EXPECT_TRUE(json["part"]["search_candidates"][0].contains("curvature_disagreement"));
  // Some of them, polished before the choice, are marked as its finalists.
  long finalists = 0;
  for (const nlohmann::json& candidate : json["part"]["search_candidates"])
    finalists += candidate.at("finalist").get<bool>();
  EXPECT_GE(finalists, 1);
  EXPECT_LE(finalists, 6);

  const ShellRun eval = run_shell(cli_ + " eval meshes/part.ply meshes/creature_moved.ply " + map.string() +
                                  " --dataset " + dir_->string() + " --gt-kind index_map:gt/part_to_moved.txt --json");
  ASSERT_EQ(eval.exit_code, 0) << eval.output;
  const nlohmann::json score = nlohmann::json::parse(eval.output.substr(eval.output.find('{')));
  EXPECT_LT(score["d_grd"].get<double>(), 0.03);
}

TEST_F(MatchCommand, EvalReadsTheBinaryAndNumpyMapsMatchWrites) {
  const std::string eval_pair = cli_ + " eval meshes/creature.ply meshes/creature_moved.ply ";
  const std::string dataset = " --dataset " + dir_->string();
  for (const std::string name : {"out.bin", "out.npy"}) {
    const fs::path map = *dir_ / name;
    const ShellRun match = run_shell(cli_ + " match " + (*dir_ / "meshes/creature.ply").string() + " " +
                                         (*dir_ / "meshes/creature_moved.ply").string() + " -o " + map.string());
    ASSERT_EQ(match.exit_code, 0) << match.output;
    const ShellRun eval = run_shell(eval_pair + map.string() + dataset + " --json");
    ASSERT_EQ(eval.exit_code, 0) << eval.output;
    EXPECT_LT(nlohmann::json::parse(eval.output.substr(eval.output.find('{')))["d_grd"].get<double>(), 0.01) << name;
  }
  std::ifstream numpy(*dir_ / "out.npy", std::ios::binary);
  std::string head(6, '\0');
  numpy.read(head.data(), 6);
  EXPECT_EQ(head, std::string("\x93NUMPY"));

  const fs::path cut = *dir_ / "cut.bin";  // declares 5 indices, holds one
  std::ofstream(cut, std::ios::binary) << std::string("ICMAP1\0\0\5\0\0\0\1\0\0\0", 16);
  const ShellRun refused = run_shell(eval_pair + cut.string() + dataset);
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.output.find("truncated"), std::string::npos) << refused.output;
}

TEST_F(MatchCommand, BadMeshIsExitCodeTwoWithAReason) {
  const fs::path bad = *dir_ / "bad.off";
  std::ofstream(bad) << "OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n";
  const ShellRun match = run_shell(cli_ + " match " + bad.string() + " " + bad.string() + " -o " + (*dir_ / "x.map").string());
  EXPECT_EQ(match.exit_code, 2);
  EXPECT_NE(match.output.find("bad.off"), std::string::npos) << match.output;
}

// A mesh the match cannot use is refused before it starts, naming the file and its role
// (the match itself would only say what is wrong, not with which of the two).
TEST_F(MatchCommand, UnusableMeshIsRefusedNamingTheFileAndItsRole) {
  const fs::path tiny = *dir_ / "tetrahedron.off", empty = *dir_ / "empty.off", map = *dir_ / "never.map";
  std::ofstream(tiny) << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
  std::ofstream{empty};
  const std::string creature = (*dir_ / "meshes/creature.ply").string();
  const ShellRun small = run_shell(cli_ + " match " + creature + " " + tiny.string() + " -o " + map.string());
  EXPECT_EQ(small.exit_code, 2);
  EXPECT_NE(small.output.find("target mesh '" + tiny.string() + "': "), std::string::npos) << small.output;
  EXPECT_NE(small.output.find("at least 16"), std::string::npos) << small.output;
  const ShellRun nothing = run_shell(cli_ + " match " + empty.string() + " " + creature + " -o " + map.string());
  EXPECT_EQ(nothing.exit_code, 2);
  EXPECT_NE(nothing.output.find("source mesh '" + empty.string() + "': the mesh file is empty"), std::string::npos)
      << nothing.output;
  EXPECT_FALSE(fs::exists(map));
}

// The heap is asked for huge pages (huge_page_malloc.h) unless the user set GLIBC_TUNABLES,
// even to nothing. The mesh is malformed: the command ends quickly, after its log's start.
TEST_F(MatchCommand, RunsWithHugePageMallocUnlessTheUserSetsTunables) {
  const fs::path bad = *dir_ / "bad_tunables.off";
  std::ofstream(bad) << "OFF\n0 0 0\n";
  const std::string args = " -v match " + bad.string() + " " + bad.string() + " -o " + (*dir_ / "x.map").string();
  const ShellRun by_default = run_shell("env -u GLIBC_TUNABLES " + cli_ + args);
  EXPECT_EQ(by_default.exit_code, 2);
  EXPECT_NE(by_default.output.find("GLIBC_TUNABLES=glibc.malloc.hugetlb=1\n"), std::string::npos) << by_default.output;
  const ShellRun opted_out = run_shell("env GLIBC_TUNABLES= " + cli_ + args);
  EXPECT_EQ(opted_out.exit_code, 2);
  EXPECT_NE(opted_out.output.find("GLIBC_TUNABLES=\n"), std::string::npos) << opted_out.output;
}

TEST_F(MatchCommand, HelpListsTheSettings) {
  const ShellRun help = run_shell(cli_ + " match --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("--level0-samples"), std::string::npos);
  EXPECT_NE(help.output.find("--selection"), std::string::npos);
  // In the table's sections, and naming other settings by their flags.
  EXPECT_NE(help.output.find("Matching settings: Per-mesh preprocessing"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("at most --zoomout-k-end"), std::string::npos) << help.output;
  EXPECT_EQ(help.output.find("zoomout_k_end"), std::string::npos) << help.output;
  EXPECT_EQ(run_shell(cli_ + " frobnicate").exit_code, 2);
}

// Settings that disagree are refused naming them as the user wrote them: by their flags.
TEST_F(MatchCommand, SettingErrorsNameTheFlags) {
  const ShellRun match = run_shell(cli_ + " match " + (*dir_ / "meshes/creature.ply").string() + " " +
                                   (*dir_ / "meshes/creature_moved.ply").string() + " -o " +
                                   (*dir_ / "never.map").string() + " --zoomout-k-end 300 --spectral-basis 200");
  EXPECT_EQ(match.exit_code, 2);
  EXPECT_NE(match.output.find("--zoomout-k-end = 300 exceeds --spectral-basis = 200"), std::string::npos)
      << match.output;
}

}  // namespace
