#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/manifest.h"

using namespace sphfx;
namespace fs = std::filesystem;

TEST(FrameFiles, FilmNaming) {
  EXPECT_EQ(framePath("shot/cache", "particles", 1, "vdb"), "shot/cache/particles.0001.vdb");
  EXPECT_EQ(framePath("d", "mesh", 1001, "ply"), "d/mesh.1001.ply");
  EXPECT_EQ(framePath("d", "mesh", 12345, "ply"), "d/mesh.12345.ply");
  EXPECT_EQ(framePath("d", "mesh", -3, "ply"), "d/mesh.-0003.ply");
}

TEST(FrameFiles, Ranges) {
  EXPECT_EQ(parseFrameRange("1001-1048").count(), 48);
  EXPECT_EQ(parseFrameRange("7").first, 7);
  EXPECT_EQ(parseFrameRange("-5--1").last, -1);
  const FrameRange scene{1, 10};
  EXPECT_THROW(parseFrameRange("5-11", &scene), InputError);
  EXPECT_THROW(parseFrameRange("9-3"), InputError);
  EXPECT_THROW(parseFrameRange("a-b"), InputError);
}

TEST(FrameFiles, AtomicWriteLeavesNoPartialFile) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_atomic_test";
  fs::remove_all(dir);
  const std::string path = (dir / "a.0001.txt").string();
  writeTextAtomically(path, "first");
  EXPECT_THROW(writeFileAtomically(path,
                                   [](const std::string& tmp) {
                                     std::ofstream(tmp) << "partial";
                                     throw IoError("disk full");
                                   }),
               IoError);
  EXPECT_EQ(readTextFile(path), "first");  // the old file survives a failed write
  size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u);  // the temporary is gone too
  writeTextAtomically((dir / "a.0003.txt").string(), "x");
  EXPECT_EQ(listFrames(dir.string(), "a", "txt"), (std::vector<int>{1, 3}));
  fs::remove_all(dir);
}

TEST(Manifest, UpdatesMerge) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_manifest_test";
  fs::remove_all(dir);
  updateManifest(dir.string(), [](ManifestJson& m) { m["simulate"]["frames"] = 3; });
  updateManifest(dir.string(), [](ManifestJson& m) { m["surface"]["frames"] = 2; });
  const ManifestJson m = readManifest(dir.string());
  EXPECT_EQ(m["manifest_version"], kManifestVersion);
  EXPECT_EQ(m["simulate"]["frames"], 3);
  EXPECT_EQ(m["surface"]["frames"], 2);
  fs::remove_all(dir);
}
