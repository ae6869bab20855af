// Where sphfx finds its shipped data: beside the executable (the build tree mirrors the install layout),
// or in $SPHFX_DATA_DIR; and how a relative input path falls back to it.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>

#include "sphfx/core/data_files.h"
#include "sphfx/core/error.h"

namespace fs = std::filesystem;
using namespace sphfx;

namespace {

/// Sets SPHFX_DATA_DIR for one test and restores the previous state.
class DataDirEnv {
 public:
  explicit DataDirEnv(const std::string& value) {
    if (const char* old = std::getenv("SPHFX_DATA_DIR")) old_ = old;
    setenv("SPHFX_DATA_DIR", value.c_str(), 1);
  }
  ~DataDirEnv() {
    if (old_.empty())
      unsetenv("SPHFX_DATA_DIR");
    else
      setenv("SPHFX_DATA_DIR", old_.c_str(), 1);
  }

 private:
  std::string old_;
};

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sphfx_data_files_" + name + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

TEST(DataFiles, BesideTheExecutableInTheBuildTree) {
  unsetenv("SPHFX_DATA_DIR");
  const fs::path dir = dataDirectory();
  EXPECT_EQ(dir, (fs::path(executablePath()).parent_path() / ".." / "share" / "sphfx").lexically_normal());
  EXPECT_TRUE(fs::exists(dir / "scenes" / "dam_break.json"));
  EXPECT_TRUE(fs::exists(dir / "studies" / "stability.json"));
  EXPECT_TRUE(fs::exists(dir / "studies" / "reference" / "dam_break_martin_moyce_n2.csv"));
}

TEST(DataFiles, EnvironmentOverridesAndMissingFolderIsAnError) {
  const fs::path dir = scratch("env");
  {
    DataDirEnv env(dir.string());
    EXPECT_EQ(dataDirectory(), dir.string());
  }
  DataDirEnv missing((dir / "absent").string());
  EXPECT_THROW(dataDirectory(), IoError);
  fs::remove_all(dir);
}

TEST(DataFiles, RelativeInputFallsBackToTheShippedFile) {
  const fs::path dir = scratch("fallback");
  fs::create_directories(dir / "scenes");
  std::ofstream(dir / "scenes" / "only_shipped.json") << "{}";
  DataDirEnv env(dir.string());
  EXPECT_EQ(resolveInputFile("scenes/only_shipped.json"), (dir / "scenes" / "only_shipped.json").string());
  // Neither here nor shipped: unchanged, so the caller's error names what the user typed.
  EXPECT_EQ(resolveInputFile("scenes/nowhere.json"), "scenes/nowhere.json");
  // Absolute paths are never redirected.
  EXPECT_EQ(resolveInputFile("/nowhere/scenes/only_shipped.json"), "/nowhere/scenes/only_shipped.json");
  // A file that exists here wins over the shipped one.
  const fs::path here = scratch("here");
  fs::create_directories(here / "scenes");
  std::ofstream(here / "scenes" / "only_shipped.json") << "{}";
  const fs::path cwd = fs::current_path();
  fs::current_path(here);
  EXPECT_EQ(resolveInputFile("scenes/only_shipped.json"), "scenes/only_shipped.json");
  fs::current_path(cwd);
  fs::remove_all(dir);
  fs::remove_all(here);
}
