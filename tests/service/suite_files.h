// A temporary directory of input files made once per test suite, and a fresh data
// directory per test, for the service tests.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace isocorr::testing {

template <typename Suite>
class WithSuiteFiles : public ::testing::Test {
 protected:
  // Creates the suite's directory, empty; SetUpTestSuite then writes its files there.
  static void make_suite_dir(const std::string& prefix) {
    dir_ = new std::filesystem::path(std::filesystem::temp_directory_path() /
                                     (prefix + "_" + std::to_string(getpid())));
    std::filesystem::remove_all(*dir_);
    std::filesystem::create_directories(*dir_);
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
    dir_ = nullptr;
  }
  static std::filesystem::path path(const std::string& name) { return *dir_ / name; }
  std::filesystem::path data_dir() const {
    return *dir_ / (std::string("data_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }

 private:
  inline static std::filesystem::path* dir_ = nullptr;
};

}  // namespace isocorr::testing
