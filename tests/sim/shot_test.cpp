// The shot level: caches through OpenVDB, determinism (two runs, byte-identical caches) and resume
// (an interrupted run continued with --resume equals an uninterrupted run).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "sim_test_util.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/sim/simulation.h"

using namespace sphfx;
namespace fs = std::filesystem;

namespace {

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Caches are compared whole, byte for byte: core writes a content-derived archive UUID (vdb_io), so two
// runs of the same state give the same file.
void expectSameCache(const std::string& a, const std::string& b) {
  const std::string x = bytes(a), y = bytes(b);
  ASSERT_FALSE(x.empty()) << a;
  ASSERT_EQ(x.size(), y.size()) << a << " vs " << b;
  EXPECT_TRUE(x == y) << a << " and " << b << " differ";
}

Scene shotScene(int endFrame) {
  return loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json",
                   {"fluid.spacing=0.025", "time.end_frame=" + std::to_string(endFrame),
                    "cache.attributes=[\"density\",\"id\"]"});
}

TEST(Shot, TwoRunsGiveIdenticalCachesAndResumeEqualsUninterrupted) {
  auto ctx = test::makeContext();
  const std::string a = test::simulateTestShot("a", shotScene(6), false);
  const std::string b = test::simulateTestShot("b", shotScene(6), false);
  test::simulateTestShot("c", shotScene(3), false);                       // "killed" after frame 3 ...
  const std::string c = test::simulateTestShot("c", shotScene(6), true);  // ... and resumed
  for (int f = 1; f <= 6; ++f) {
    expectSameCache(particleCachePath(a, f), particleCachePath(b, f));
    expectSameCache(particleCachePath(a, f), particleCachePath(c, f));
  }
  // The caches read back through OpenVDB with every particle and attribute.
  const ParticleFrame frame = readParticleCache(particleCachePath(a, 6));
  EXPECT_EQ(frame.frame, 6);
  EXPECT_EQ(frame.size(), countInitialParticles(shotScene(6)));
  EXPECT_EQ(frame.density.size(), frame.size());
  EXPECT_EQ(frame.id.size(), frame.size());
  // Only the latest restart file is kept; the manifest lists every frame once.
  EXPECT_TRUE(fs::exists(c + "/cache/.restart.0006.bin"));
  EXPECT_FALSE(fs::exists(c + "/cache/.restart.0003.bin"));
  const ManifestJson m = readManifest(c);
  EXPECT_EQ(m["simulate"]["status"], "complete");
  EXPECT_EQ(m["simulate"]["per_frame"].size(), 6u);
  EXPECT_EQ(m["simulate"]["frames_written"], 6);
  EXPECT_EQ(m["simulate"]["particle_count"], frame.size());
}

}  // namespace
