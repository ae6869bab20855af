// Particle cache round trip through OpenVDB, checked against the written arrays and against OpenVDB's
// own reading of the file (independent of our reader).
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/PointCount.h>
#include <openvdb/points/PointDataGrid.h>

#include <filesystem>
#include <map>
#include <random>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/particle_cache.h"

using namespace sphfx;
namespace fs = std::filesystem;

namespace {
ParticleFrame randomFrame(size_t n, bool extras) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> u(-1.0f, 3.0f);
  ParticleFrame f;
  f.frame = 1001;
  f.time = 0.5;
  f.particleSpacing = 0.02;
  for (size_t i = 0; i < n; ++i) {
    f.position.push_back({u(rng), u(rng), u(rng)});
    f.velocity.push_back({u(rng), u(rng), u(rng)});
    if (extras) {
      f.density.push_back(1000 + u(rng));
      f.pressure.push_back(u(rng) * 100);
      f.id.push_back(int32_t(i));
    }
  }
  return f;
}
}  // namespace

TEST(ParticleCache, RoundTripWithAllAttributes) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_cache_test";
  fs::remove_all(dir);
  const ParticleFrame written = randomFrame(5000, true);
  const std::string path = particleCachePath(dir.string(), written.frame);
  EXPECT_EQ(fs::path(path).filename(), "particles.1001.vdb");
  writeParticleCache(path, written);
  const ParticleFrame read = readParticleCache(path);
  EXPECT_EQ(read.frame, 1001);
  EXPECT_DOUBLE_EQ(read.time, 0.5);
  EXPECT_DOUBLE_EQ(read.particleSpacing, 0.02);
  ASSERT_EQ(read.size(), written.size());
  ASSERT_EQ(read.id.size(), written.size());
  // Storage order is by voxel; match particles through their ids.
  for (size_t k = 0; k < read.size(); ++k) {
    const size_t i = size_t(read.id[k]);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(read.position[k][a], written.position[i][a], 1e-6f);
      EXPECT_EQ(read.velocity[k][a], written.velocity[i][a]);
    }
    EXPECT_EQ(read.density[k], written.density[i]);
    EXPECT_EQ(read.pressure[k], written.pressure[i]);
  }
  // The surfacing stage's read: the same positions in the same order, nothing else.
  const ParticleFrame positions = readParticleCache(path, CacheFields::Positions);
  EXPECT_EQ(positions.frame, read.frame);
  EXPECT_EQ(positions.particleSpacing, read.particleSpacing);
  EXPECT_EQ(positions.position, read.position);
  EXPECT_TRUE(positions.velocity.empty() && positions.density.empty() && positions.pressure.empty() &&
              positions.id.empty());
  fs::remove_all(dir);
}

TEST(ParticleCache, OptionalAttributesAreLeftOut) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_cache_test2";
  const std::string path = (dir / "particles.0001.vdb").string();
  writeParticleCache(path, randomFrame(100, false));
  // Read with OpenVDB directly: the grid is a PointDataGrid named "points" with exactly P and v.
  openvdb::initialize();
  openvdb::io::File file(path);
  file.open();
  auto grid = openvdb::gridPtrCast<openvdb::points::PointDataGrid>(file.readGrid("points"));
  file.close();
  ASSERT_TRUE(grid);
  EXPECT_EQ(openvdb::points::pointCount(grid->tree()), 100u);
  const auto& desc = grid->tree().cbeginLeaf()->attributeSet().descriptor();
  EXPECT_EQ(desc.size(), 2u);
  EXPECT_NE(desc.find("v"), openvdb::points::AttributeSet::INVALID_POS);
  EXPECT_TRUE(readParticleCache(path).density.empty());
  fs::remove_all(dir);
}

TEST(ParticleCache, RejectsWhatIsNotACache) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_cache_test3";
  fs::create_directories(dir);
  writeTextAtomically((dir / "junk.vdb").string(), "not a vdb");
  EXPECT_THROW(readParticleCache((dir / "junk.vdb").string()), Error);
  ParticleFrame bad = randomFrame(10, false);
  bad.velocity.pop_back();
  EXPECT_THROW(writeParticleCache((dir / "bad.vdb").string(), bad), InputError);
  EXPECT_FALSE(fs::exists(dir / "bad.vdb"));
  fs::remove_all(dir);
}

TEST(ParticleCache, EmptyFrame) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_cache_test4";
  ParticleFrame f;
  f.particleSpacing = 0.1;
  writeParticleCache((dir / "e.vdb").string(), f);
  EXPECT_EQ(readParticleCache((dir / "e.vdb").string()).size(), 0u);
  fs::remove_all(dir);
}

TEST(ParticleCache, SameFrameGivesIdenticalBytes) {
  // OpenVDB stamps a random UUID into every archive; the cache replaces it by a content hash.
  const fs::path dir = fs::temp_directory_path() / "sphfx_cache_test5";
  const ParticleFrame f = randomFrame(2000, true);
  writeParticleCache((dir / "a.vdb").string(), f);
  writeParticleCache((dir / "b.vdb").string(), f);
  EXPECT_EQ(readTextFile((dir / "a.vdb").string()), readTextFile((dir / "b.vdb").string()));
  ParticleFrame g = f;
  g.velocity[7][1] += 1.0f;
  writeParticleCache((dir / "c.vdb").string(), g);
  const std::string a = readTextFile((dir / "a.vdb").string()), c = readTextFile((dir / "c.vdb").string());
  EXPECT_NE(a.substr(21, 36), c.substr(21, 36));  // a different frame gets a different UUID
  fs::remove_all(dir);
}
