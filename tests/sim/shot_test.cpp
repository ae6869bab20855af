// The shot level: caches through OpenVDB, determinism (two runs, byte-identical caches) and resume
// (an interrupted run continued with --resume equals an uninterrupted run); the hardware GPUs' and the
// CPU rasterisers' reductions give the same run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

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

class ShotReductions : public test::SolverTest {};

// SIM_WORKGROUP_REDUCE (hardware GPUs: shared-memory reductions and grid scans per work group) against
// the CPU rasterisers' per-invocation atomics, per-particle residuals and serial scan blocks, forced on
// one device: the scans give the same integers, so the same grids; the largest speed, acceleration and
// density do not depend on the order they are taken in, so the steps, and with them the caches, are the
// same bytes. DFSPH's residual averages are sums in another order; they decide when a solve stops, so
// the same caches also say that every decision came out the same.
TEST_P(ShotReductions, BothReductionsGiveTheSameCaches) {
  const Scene scene =
      loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json",
                {"fluid.spacing=0.025", "time.end_frame=4", "cache.attributes=[\"density\",\"pressure\"]",
                 "solver.method=" + GetParam()});
  std::string shots[2];
  for (int reduce : {0, 1}) {
    const test::ScopedEnv env("SPHFX_WORKGROUP_REDUCE", reduce ? "1" : "0");
    shots[reduce] = test::simulateTestShot("reduce" + std::to_string(reduce) + GetParam(), scene);
  }
  const ManifestJson a = readManifest(shots[0]), b = readManifest(shots[1]);
  for (int f = 1; f <= 4; ++f) {
    expectSameCache(particleCachePath(shots[0], f), particleCachePath(shots[1], f));
    EXPECT_EQ(a["simulate"]["per_frame"][size_t(f - 1)]["substeps"],
              b["simulate"]["per_frame"][size_t(f - 1)]["substeps"]);
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, ShotReductions, ::testing::Values("wcsph", "dfsph"), test::solverParamName);

class ShotSampleSkip : public test::SolverTest {};

// The wall samples' passes skip a sample that no particle's walk reached and that had no fluid near at
// its last pass (DFSPH_SAMPLES_MARKED in sph_dfsph.glsl, sim_boundary_pressure.comp): what it would
// write is what its slot holds. Against SPHFX_VISIT_EVERY_SAMPLE=1, which visits every sample every
// substep, the caches are the same bytes: a dam break whose surge wets the floor and runs up the far wall
// (samples reached, then left), and the same with a box rising through the fluid (colliders re-sort the
// samples every substep, so a slot's sample changes).
TEST_P(ShotSampleSkip, SkippingSamplesWithoutFluidNearChangesNoCache) {
  constexpr int kFrames = 12;  // 0.4 s: the surge reaches the far wall at about 0.3 s
  const std::string box = R"(colliders=[{"shape": "box", "min": [0.45, 0.0, 0.0], "max": [0.55, 0.05, 0.1],
      "keyframes": [{"time": 0.0, "offset": [0, 0, 0]}, {"time": 0.4, "offset": [0, 0.2, 0]}]}])";
  for (const bool collider : {false, true}) {
    std::vector<std::string> overrides = {"fluid.spacing=0.025", "time.end_frame=" + std::to_string(kFrames),
                                          "cache.attributes=[\"density\",\"pressure\"]",
                                          "solver.method=" + GetParam()};
    if (collider) overrides.push_back(box);
    const Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json", overrides);
    std::string shots[2];
    for (int every : {0, 1}) {
      const test::ScopedEnv env("SPHFX_VISIT_EVERY_SAMPLE", every ? "1" : "0");
      shots[every] = test::simulateTestShot(
          "samples" + std::to_string(every) + (collider ? "box" : "") + GetParam(), scene);
    }
    for (int f = 1; f <= kFrames; ++f)
      expectSameCache(particleCachePath(shots[0], f), particleCachePath(shots[1], f));
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, ShotSampleSkip, ::testing::Values("wcsph", "dfsph"), test::solverParamName);

}  // namespace
