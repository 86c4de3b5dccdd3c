#pragma once
// Helpers the tests share: a scratch directory per test, the message of an expected InputError.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"

class TempDir {
 public:
  TempDir() {
    const auto* test = ::testing::UnitTest::GetInstance();
    path_ = std::filesystem::temp_directory_path() /
            ("poreshell-" + std::to_string(test->random_seed()) + "-" +
             test->current_test_info()->test_suite_name() + "-" + test->current_test_info()->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  // Writes `contents` to a file of that name in the directory.
  std::filesystem::path file(const std::string& name, const std::string& contents) const {
    const std::filesystem::path p = path_ / name;
    std::ofstream(p, std::ios::binary) << contents;
    return p;
  }

 private:
  std::filesystem::path path_;
};

// The message of the poreshell::Error (bad input or option) that `f` throws, or "" if it throws none.
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const poreshell::Error& e) {
    return e.what();
  }
  return "";
}
