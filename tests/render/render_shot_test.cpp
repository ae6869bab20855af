// The shot-level render stage: frames from a small synthetic shot (particle caches and meshes on disk),
// skipping, manifest, contact sheet; and image regression against committed references.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "render_test_util.h"
#include "sphfx/core/error.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/mesh_io.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/render/render_shot.h"

using namespace sphfx;
using namespace sphfx::render;
namespace fs = std::filesystem;

namespace {

class RenderShot : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ctx_ = test::makeContext(); }
  static void TearDownTestSuite() { ctx_.reset(); }
  static std::unique_ptr<GLContext> ctx_;
};
std::unique_ptr<GLContext> RenderShot::ctx_;

/// A small dam-break-like tank with a moving box collider.
const char* kSceneJson = R"({
  "name": "render_test",
  "domain": { "min": [0, 0, 0], "max": [0.6, 0.4, 0.2] },
  "fluid": { "spacing": 0.02, "blocks": [ { "shape": "box", "min": [0, 0, 0], "max": [0.2, 0.3, 0.2] } ] },
  "time": { "fps": 10, "start_frame": 1, "end_frame": 3 },
  "colliders": [ { "name": "post", "shape": "box", "min": [0.4, 0, 0.06], "max": [0.46, 0.2, 0.12],
                   "keyframes": [ { "time": 0, "offset": [0, 0, 0] }, { "time": 0.2, "offset": [0.05, 0, 0] } ] } ],
  "render": { "width": 160, "height": 90, "samples": 4, "source": "particles" }
})";

/// A deterministic particle frame: the seeded block, slumping and moving right with time.
ParticleFrame syntheticFrame(const Scene& scene, int frame) {
  const SeededParticles seed = seedParticles(scene);
  ParticleFrame f;
  f.frame = frame;
  f.time = scene.frameTime(frame);
  f.particleSpacing = scene.fluid.spacing;
  for (size_t i = 0; i < seed.position.size(); ++i) {
    auto p = seed.position[i];
    const float s = float(f.time) * 1.5f;
    p[0] += s * p[0] * (0.4f - p[1]) * 3.0f;
    p[1] *= 1.0f - 0.4f * s;
    f.position.push_back(p);
    f.velocity.push_back({s * 2.0f * (0.3f - p[1]), -s, 0});
  }
  return f;
}

/// A blobby water mesh: a squashed sphere sitting in the tank.
TriangleMesh syntheticMesh() {
  TriangleMesh m = makeUvSphere({0.2, 0.1, 0.1}, 0.14, 24, 48);
  for (auto& p : m.positions) p[1] = 0.1f + (p[1] - 0.1f) * 0.7f;
  return m;
}

std::string writeShot(const std::string& name, Scene& scene) {
  const std::string shot = test::tempDir(name);
  std::ofstream(shot + "/scene.json") << kSceneJson;
  scene = loadScene(shot + "/scene.json");
  for (int f = 1; f <= 3; ++f) {
    writeParticleCache(particleCachePath(shot, f), syntheticFrame(scene, f));
    writePly(meshPath(shot, f), syntheticMesh());
  }
  return shot;
}

/// Mean and max absolute channel difference (8-bit levels) and the fraction of pixels off by more
/// than 16 levels.
struct Diff {
  double mean = 0, max = 0, over16 = 0;
};
Diff compare(const Image8& a, const Image8& b) {
  Diff d;
  size_t bad = 0;
  for (size_t i = 0; i < a.rgb.size(); i += 3) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int e = std::abs(int(a.rgb[i + c]) - int(b.rgb[i + c]));
      d.mean += e;
      worst = std::max(worst, e);
    }
    d.max = std::max(d.max, double(worst));
    bad += worst > 16;
  }
  d.mean /= double(a.rgb.size());
  d.over16 = double(bad) / double(a.rgb.size() / 3);
  return d;
}

/// Compares a rendered frame with tests/data/render/NAME.png; with SPHFX_UPDATE_REFERENCES=1 rewrites
/// the reference instead (then inspect it and commit it).
void checkReference(const std::string& renderedPng, const std::string& name) {
  const std::string ref = std::string(SPHFX_SOURCE_DIR) + "/tests/data/render/" + name + ".png";
  const char* update = std::getenv("SPHFX_UPDATE_REFERENCES");
  if (update && std::string(update) == "1") {
    fs::copy_file(renderedPng, ref, fs::copy_options::overwrite_existing);
    GTEST_SKIP() << "reference rewritten: " << ref;
  }
  const Image8 got = readPng(renderedPng), want = readPng(ref);
  ASSERT_EQ(got.width, want.width);
  ASSERT_EQ(got.height, want.height);
  const Diff d = compare(got, want);
  ::testing::Test::RecordProperty("mean_error", std::to_string(d.mean));
  ::testing::Test::RecordProperty("max_error", std::to_string(d.max));
  // Thresholds (docs/rendering.md): rounding between rasterisers moves edge samples and a level or two
  // of shading; a wrong camera, colour ramp or missing object moves far more.
  EXPECT_LE(d.mean, 1.5) << name << ": mean channel error (8-bit levels)";
  EXPECT_LE(d.over16, 0.01) << name << ": fraction of pixels off by more than 16 levels";
  EXPECT_LE(d.max, 96) << name << ": max channel error";
}

}  // namespace

TEST_F(RenderShot, ParticlesFramesManifestSkipAndContactSheet) {
  Scene scene;
  const std::string shot = writeShot("particles_shot", scene);
  RenderShotOptions o;
  o.shotDir = shot;
  o.contactEvery = 2;
  const RenderShotResult r = renderShot(scene, o);
  EXPECT_EQ(r.rendered, 3);
  EXPECT_EQ(r.skipped, 0);
  for (int f = 1; f <= 3; ++f) {
    const Image8 img = readPng(renderPath(shot, "particles", f, "png"));
    EXPECT_EQ(img.width, 160);
    EXPECT_EQ(img.height, 90);
  }
  const ManifestJson m = readManifest(shot);
  ASSERT_TRUE(m.contains("render"));
  EXPECT_EQ(m["render"]["frames"].size(), 3u);
  EXPECT_GT(m["render"]["frames"]["0002"]["seconds"].get<double>(), 0.0);
  EXPECT_EQ(m["render"]["samples"].get<int>(), 4);
  EXPECT_EQ(m["render"]["renderer"].get<std::string>(), r.renderer);
  // Frames 1 and 3 at 2 columns' worth of thumbnails (160 wide, 4 px gutters), one row.
  const Image8 sheet = readPng(shot + "/render/particles_contact.png");
  EXPECT_EQ(sheet.width, 2 * 160 + 3 * 4);
  EXPECT_EQ(sheet.height, 90 + 2 * 4);

  const RenderShotResult again = renderShot(scene, o);
  EXPECT_EQ(again.rendered, 0);
  EXPECT_EQ(again.skipped, 3);
  o.force = true;
  o.frames = FrameRange{2, 2};
  EXPECT_EQ(renderShot(scene, o).rendered, 1);
  checkReference(renderPath(shot, "particles", 2, "png"), "particles_160x90");
}

TEST_F(RenderShot, SurfaceFrameMatchesReference) {
  Scene scene;
  const std::string shot = writeShot("surface_shot", scene);
  RenderShotOptions o;
  o.shotDir = shot;
  o.source = RenderSource::Surface;
  o.frames = FrameRange{2, 2};
  EXPECT_EQ(renderShot(scene, o).rendered, 1);
  checkReference(renderPath(shot, "surface", 2, "png"), "surface_160x90");
}

TEST_F(RenderShot, ExrFramesCarryDepth) {
  Scene scene;
  const std::string shot = writeShot("exr_shot", scene);
  RenderShotOptions o;
  o.shotDir = shot;
  o.format = ImageFormat::Exr;
  o.frames = FrameRange{1, 1};
  renderShot(scene, o);
  const Image img = readExrRgba(renderPath(shot, "particles", 1, "exr"));
  EXPECT_EQ(img.width, 160);
  EXPECT_TRUE(fs::exists(shot + "/render/particles_contact.png"));
}

TEST_F(RenderShot, SceneFromManifestAndInputErrors) {
  Scene scene;
  const std::string shot = writeShot("errors_shot", scene);
  EXPECT_THROW(loadShotScene(shot), InputError);  // nothing recorded yet
  updateManifest(shot, [&](ManifestJson& m) { m["simulate"]["scene"] = sceneToJson(scene); });
  EXPECT_EQ(loadShotScene(shot).name, "render_test");
  EXPECT_THROW(loadShotScene(shot + "/missing"), InputError);
  RenderShotOptions o;
  o.shotDir = shot;
  o.frames = FrameRange{1, 5};  // frames 4 and 5 have no cache
  EXPECT_THROW(renderShot(scene, o), InputError);
  fs::remove_all(shot + "/mesh");
  o.frames.reset();
  o.source = RenderSource::Surface;
  EXPECT_THROW(renderShot(scene, o), InputError);
}
