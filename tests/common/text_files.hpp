// Whole files for the tests that drive statepack's programs: read as bytes, and written as a plain save
// does (truncate, then write; the directories made first).
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace statepack::testing {

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

inline void write_file(const std::filesystem::path& path, const std::string& text) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// A new, empty directory `base`/`group`/<the running test's name>: ctest runs tests at once, so each one
// writes where no other does, and nothing an earlier run left is read.
inline std::filesystem::path fresh_test_dir(const std::filesystem::path& base, const std::string& group) {
  const std::filesystem::path dir =
      base / group / ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace statepack::testing
