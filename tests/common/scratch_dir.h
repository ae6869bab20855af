// Scratch folders for the tests' files, all under one folder per test process, TMP/sphfx_test_PID, which
// goes when the process exits with every test passed. A process with a failed test keeps it for inspection
// and says where; a crashed or killed one leaves it.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

namespace sphfx::test {

/// The process's scratch folder. Destroyed at exit, before gtest's UnitTest (constructed earlier, at test
/// registration), so the destructor can still ask whether every test passed.
class ScratchRoot {
 public:
  ScratchRoot()
      : path_(std::filesystem::temp_directory_path() / ("sphfx_test_" + std::to_string(::getpid()))) {}
  ~ScratchRoot() {
    if (!std::filesystem::exists(path_)) return;
    if (::testing::UnitTest::GetInstance()->Failed()) {
      std::fprintf(stderr, "test files kept in %s\n", path_.c_str());
      return;
    }
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchRoot(const ScratchRoot&) = delete;
  ScratchRoot& operator=(const ScratchRoot&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// TMP/sphfx_test_PID/NAME, with its parent created; NAME itself is neither created nor emptied (callers
/// that resume a shot keep its files). Throws std::filesystem::filesystem_error if the parent cannot be made.
inline std::filesystem::path scratchPath(const std::string& name) {
  static ScratchRoot root;
  std::filesystem::create_directories(root.path());
  return root.path() / name;
}

}  // namespace sphfx::test
