#pragma once
// A test fixture with its own empty scratch directory, named after the test and this process (two test runs on one
// machine, or CTest's parallel jobs, never share one), and removed afterwards.

#include <filesystem>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

namespace softwrist::testing {

class ScratchDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("softwrist_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

}  // namespace softwrist::testing
