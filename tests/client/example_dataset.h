// The folder `isocorr-make-examples` writes (the creature, its moved copy, the map between
// them and a pairs.tsv), made once per test suite in a temporary folder, for the tests that
// run the real `isocorr` on it. `Subdivisions` sets the creature's size.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "shell_run.h"

namespace isocorr::testing {

template <int Subdivisions>
class ExampleDatasetTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string suite = ::testing::UnitTest::GetInstance()->current_test_suite()->name();
    dir_ = new std::filesystem::path(std::filesystem::temp_directory_path() /
                                     ("isocorr_" + suite + "_" + std::to_string(getpid())));
    std::filesystem::create_directories(*dir_);
    ASSERT_EQ(run_shell(std::string(ISOCORR_MAKE_EXAMPLES_PATH) + " " + dir_->string() + " --subdivisions " +
                        std::to_string(Subdivisions))
                  .exit_code,
              0);
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
    dir_ = nullptr;
  }
  // A file of the folder, e.g. "meshes/creature.ply".
  static std::string path(const std::string& relative) { return (*dir_ / relative).string(); }

  static inline std::filesystem::path* dir_ = nullptr;
};

}  // namespace isocorr::testing
