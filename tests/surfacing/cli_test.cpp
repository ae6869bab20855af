// The `sphfx surface` command end to end: files, independent readers, manifest, skipping, determinism
// across thread counts, and bad input.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>

#include "sphfx/core/frame_files.h"
#include "sphfx/core/manifest.h"
#include "test_util.h"

namespace sphfx {
namespace {

namespace fs = std::filesystem;

struct Result {
  int code = -1;
  std::string output;
};

/// Runs a shell command line, capturing stdout and stderr.
Result shell(const std::string& command) {
  Result r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, n);
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string exe() {
  const char* env = std::getenv("SPHFX_EXE");  // lets a developer point at another build
  return env ? env : SPHFX_EXE;
}

Result sphfx(const std::string& args) {
  return shell(exe() + " " + args);
}

constexpr double kSpacing = 0.05, kRadius = 0.4;

/// A shot with two frames: a ball of particles, and the same ball moved.
void makeShot(const std::string& shot) {
  auto ball = test::sphereLattice(kRadius, kSpacing);
  test::writeFrame(shot, 1, ball, kSpacing);
  for (auto& p : ball) p[0] += 0.13f;
  test::writeFrame(shot, 2, ball, kSpacing);
}

std::string bytes(const std::string& path) {
  return readTextFile(path);
}

TEST(Cli, WritesLevelSetsAndMeshesThatIndependentReadersAccept) {
  test::TempDir dir("files");
  const std::string shot = dir / "shot";
  makeShot(shot);
  const Result r = sphfx("surface " + shot + " --method zhu-bridson");
  ASSERT_EQ(r.code, 0) << r.output;
  const ManifestJson manifest = readManifest(shot);
  openvdb::initialize();
  for (int frame : {1, 2}) {
    openvdb::io::File file(surfacePath(shot, frame));
    file.open();
    ASSERT_TRUE(file.hasGrid("surface"));
    const auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("surface"));
    file.close();
    ASSERT_TRUE(grid) << "not a FloatGrid";
    EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
    EXPECT_GT(grid->activeVoxelCount(), 0u);

    const Result ply = shell(std::string(SPHFX_PYTHON) + " " + SPHFX_CHECK_PLY + " " + meshPath(shot, frame));
    ASSERT_EQ(ply.code, 0) << ply.output;
    size_t vertices = 0, faces = 0;
    double volume = 0, area = 0;
    ASSERT_EQ(std::sscanf(ply.output.c_str(), "vertices %zu faces %zu volume %lf area %lf", &vertices, &faces,
                          &volume, &area),
              4)
        << ply.output;
    const double v0 = 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3);
    EXPECT_NEAR(volume, v0, 0.1 * v0) << "outward-facing, closed mesh of the ball";
    const TriangleMesh mesh = readPly(meshPath(shot, frame));
    EXPECT_EQ(mesh.triangles.size(), faces);
    EXPECT_EQ(mesh.positions.size(), vertices);
    const auto& figures = manifest["surface"]["frames"][std::to_string(frame)];
    EXPECT_EQ(figures["triangles"].get<size_t>(), faces);
    EXPECT_EQ(figures["particles"].get<size_t>(), test::sphereLattice(kRadius, kSpacing).size());
    EXPECT_EQ(figures["active_voxels"].get<uint64_t>(), grid->activeVoxelCount());
  }
  EXPECT_EQ(manifest["surface"]["params"]["method"], "zhu-bridson");
}

TEST(Cli, SkipsFramesThatAreUpToDateUnlessForced) {
  test::TempDir dir("skip");
  const std::string shot = dir / "shot";
  makeShot(shot);
  ASSERT_EQ(sphfx("surface " + shot + " --method spheres").code, 0);
  const auto before = fs::last_write_time(meshPath(shot, 1));
  const Result again = sphfx("surface " + shot + " --method spheres");
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_NE(again.output.find("2 up to date"), std::string::npos) << again.output;
  EXPECT_EQ(fs::last_write_time(meshPath(shot, 1)), before);
  // Other parameters make the outputs stale.
  ASSERT_EQ(sphfx("surface " + shot + " --method spheres --smooth 1 --frames 1").code, 0);
  EXPECT_NE(fs::last_write_time(meshPath(shot, 1)), before);
  const auto second = fs::last_write_time(meshPath(shot, 1));
  ASSERT_EQ(sphfx("surface " + shot + " --method spheres --smooth 1 --frames 1 --force").code, 0);
  EXPECT_NE(fs::last_write_time(meshPath(shot, 1)), second);
}

class Determinism : public ::testing::TestWithParam<std::string> {};

TEST_P(Determinism, SameBytesWithOneAndTwoThreads) {
  test::TempDir dir("det_" + GetParam());
  const std::string a = dir / "a", b = dir / "b";
  makeShot(a);
  fs::copy(a, b, fs::copy_options::recursive);
  ASSERT_EQ(sphfx("surface " + a + " --threads 1 --method " + GetParam()).code, 0);
  ASSERT_EQ(sphfx("surface " + b + " --threads 2 --method " + GetParam()).code, 0);
  for (int frame : {1, 2}) {
    EXPECT_EQ(bytes(surfacePath(a, frame)), bytes(surfacePath(b, frame))) << "surface frame " << frame;
    EXPECT_EQ(bytes(meshPath(a, frame)), bytes(meshPath(b, frame))) << "mesh frame " << frame;
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, Determinism, ::testing::Values("spheres", "zhu-bridson", "anisotropic"),
                         [](const auto& info) {
                           std::string n = info.param;
                           return n == "zhu-bridson" ? std::string("ZhuBridson") : n;
                         });

TEST(Cli, BadInputExitsWithCode2AndSaysWhy) {
  test::TempDir dir("errors");
  const std::string shot = dir / "shot", empty = dir / "empty";
  makeShot(shot);
  fs::create_directories(empty);
  const std::vector<std::pair<std::string, std::string>> cases{
      {"surface " + dir / "missing", "no such shot directory"},
      {"surface " + empty, "no particle cache frames"},
      {"surface " + shot + " --method marching", "--method"},
      {"surface " + shot + " --voxel-size -1", "--voxel-size must be a positive length"},
      {"surface " + shot + " --radius 0", "--radius must be a positive length"},
      {"surface " + shot + " --adaptivity 2", "--adaptivity must be in [0, 1]"},
      {"surface " + shot + " --smooth -3", "--smooth must be 0 or more"},
      {"surface " + shot + " --threads 0", "--threads must be 1 or more"},
      {"surface " + shot + " --frames 7-9", "7-9"},
      {"surface " + shot + " --frames abc", "abc"},
  };
  for (const auto& [args, expected] : cases) {
    const Result r = sphfx(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(expected), std::string::npos) << args << "\n" << r.output;
  }
}

}  // namespace
}  // namespace sphfx
