// The shot-level render stage: frames from a small synthetic shot (particle caches and meshes on disk),
// skipping, manifest, contact sheet; and image regression of a real (tiny) dam-break frame against
// committed references (tests/data/render/dam_break_tiny).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>

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

/// Differences of two images in 8-bit levels: `mean`, the mean absolute channel difference, pixel by
/// pixel; `max`, the largest channel difference of a pixel to the best-matching pixel of the other image
/// within one pixel of it (edges that a rasteriser places a pixel over cost nothing there; colours that
/// are nowhere near do).
struct Diff {
  double mean = 0, max = 0;
};

int pixelDistance(const Image8& a, int ax, int ay, const Image8& b, int bx, int by) {
  int worst = 0;
  for (int c = 0; c < 3; ++c)
    worst = std::max(worst, std::abs(int(a.rgb[(size_t(ay) * a.width + ax) * 3 + c]) -
                                     int(b.rgb[(size_t(by) * b.width + bx) * 3 + c])));
  return worst;
}

Diff compare(const Image8& a, const Image8& b) {
  Diff d;
  for (size_t i = 0; i < a.rgb.size(); ++i) d.mean += std::abs(int(a.rgb[i]) - int(b.rgb[i]));
  d.mean /= double(a.rgb.size());
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      int best = 255;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int bx = std::clamp(x + dx, 0, b.width - 1), by = std::clamp(y + dy, 0, b.height - 1);
          best = std::min(best, pixelDistance(a, x, y, b, bx, by));
        }
      d.max = std::max(d.max, double(best));
    }
  return d;
}

std::ostream& operator<<(std::ostream& os, const Diff& d) {
  return os << "mean " << d.mean << ", max (within a pixel) " << d.max;
}

// Regression thresholds (docs/rendering.md "Tests"), in 8-bit levels. Measured on
// the tiny dam-break frame against its 4x MSAA references (particles / surface):
//  - egl-surfaceless vs osmesa: bit-identical (mean 0, max 0).
//  - the same frame at 1 sample, a harsher change than llvmpipe vs a GPU (both use the standard 4x
//    pattern and fp32 shading): mean 0.38 / 0.34, max 36 / 18. Tolerated.
//  - wrong images, all rejected: camera moved 2 cm (1.8 px): mean 2.06 / 1.41, max 126 / 48; speed ramp
//    instead of height: mean 3.7, max 222; flipped: mean 21 / 15; water missing: mean 0.91, max 48.
//    (Particle frames are speckled: even a 0.2-pixel camera move gives max 53 there.)
constexpr double kMaxMeanError = 1.0, kMaxError = 40;

bool withinThresholds(const Diff& d) {
  return d.mean <= kMaxMeanError && d.max <= kMaxError;
}

const std::string kDamBreakDir = std::string(SPHFX_SOURCE_DIR) + "/tests/data/render/dam_break_tiny";
constexpr int kDamBreakFrame = 8;

/// The committed reference tests/data/render/dam_break_tiny/NAME.png; with SPHFX_UPDATE_REFERENCES=1,
/// `rendered` is written there first (then inspect it and commit it).
Image8 reference(const std::string& name, const Image8& rendered) {
  const std::string ref = kDamBreakDir + "/" + name + ".png";
  const char* update = std::getenv("SPHFX_UPDATE_REFERENCES");
  if (update && std::string(update) == "1") writePng(ref, rendered);
  return readPng(ref);
}

Scene damBreakScene() {
  return loadScene(kDamBreakDir + "/scene.json");
}

/// Renders the committed dam-break frame (its particle cache or its mesh) in a fresh shot directory.
Image8 renderDamBreak(const std::string& name, const Scene& scene, RenderSource source, int samples = 4) {
  const std::string shot = test::tempDir(name);
  const std::string cache = particleCachePath(shot, kDamBreakFrame), mesh = meshPath(shot, kDamBreakFrame);
  fs::create_directories(fs::path(cache).parent_path());
  fs::create_directories(fs::path(mesh).parent_path());
  fs::copy_file(kDamBreakDir + "/cache/particles.0008.vdb", cache);
  fs::copy_file(kDamBreakDir + "/mesh/mesh.0008.ply", mesh);
  RenderShotOptions o;
  o.shotDir = shot;
  o.source = source;
  o.samples = samples;
  o.frames = FrameRange{kDamBreakFrame, kDamBreakFrame};
  EXPECT_EQ(renderShot(scene, o).rendered, 1);
  return readPng(
      renderPath(shot, source == RenderSource::Surface ? "surface" : "particles", kDamBreakFrame, "png"));
}

void expectMatchesReference(const Image8& got, const std::string& name) {
  const Image8 want = reference(name, got);
  ASSERT_EQ(got.width, want.width);
  ASSERT_EQ(got.height, want.height);
  const Diff d = compare(got, want);
  ::testing::Test::RecordProperty("mean_error", std::to_string(d.mean));
  ::testing::Test::RecordProperty("max_error", std::to_string(d.max));
  EXPECT_TRUE(withinThresholds(d)) << name << ": " << d;
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
}

TEST_F(RenderShot, DamBreakCacheStillReads) {
  // The committed cache pins the on-disk format: the reader must keep reading it.
  const ParticleFrame f = readParticleCache(kDamBreakDir + "/cache/particles.0008.vdb");
  EXPECT_EQ(f.frame, kDamBreakFrame);
  EXPECT_EQ(f.size(), 1000u);  // the 10 x 20 x 5 block at 2 cm
  EXPECT_DOUBLE_EQ(f.particleSpacing, 0.02);
  const Scene scene = damBreakScene();
  EXPECT_NEAR(f.time, scene.frameTime(kDamBreakFrame), 1e-9);
  for (const auto& p : f.position)
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(p[a], scene.domain.min[a] - 0.02);
      EXPECT_LE(p[a], scene.domain.max[a] + 0.02);
    }
}

TEST_F(RenderShot, DamBreakParticlesMatchReference) {
  expectMatchesReference(renderDamBreak("dam_particles", damBreakScene(), RenderSource::Particles),
                         "particles_160x90");
}

TEST_F(RenderShot, DamBreakSurfaceMatchesReference) {
  expectMatchesReference(renderDamBreak("dam_surface", damBreakScene(), RenderSource::Surface),
                         "surface_160x90");
}

// The thresholds separate rasterisation differences from wrong pictures: the same frame without MSAA
// passes; a camera moved by 2 cm, the speed ramp instead of height, a flipped frame, and the stage without
// the water all fail.
TEST_F(RenderShot, ThresholdsTolerateRasterisationNotWrongImages) {
  const Scene scene = damBreakScene();
  for (RenderSource source : {RenderSource::Particles, RenderSource::Surface}) {
    const bool surface = source == RenderSource::Surface;
    const std::string tag = surface ? "surface" : "particles";
    SCOPED_TRACE(tag);
    const Image8 want = readPng(kDamBreakDir + "/" + tag + "_160x90.png");
    const Image8 good = renderDamBreak(tag + "_good", scene, source);

    const Diff oneSample = compare(renderDamBreak(tag + "_1x", scene, source, 1), want);
    EXPECT_TRUE(withinThresholds(oneSample)) << "1 sample: " << oneSample;

    Scene moved = scene;
    moved.render.camera->position[0] += 0.02;
    const Diff shifted = compare(renderDamBreak(tag + "_moved", moved, source), want);
    EXPECT_FALSE(withinThresholds(shifted)) << "camera moved 2 cm: " << shifted;

    Image8 flipped = good;
    const size_t row = size_t(good.width) * 3;
    for (int y = 0; y < good.height; ++y)
      std::copy_n(&good.rgb[size_t(good.height - 1 - y) * row], row, &flipped.rgb[size_t(y) * row]);
    const Diff upsideDown = compare(flipped, want);
    EXPECT_FALSE(withinThresholds(upsideDown)) << "flipped: " << upsideDown;

    if (!surface) {
      Scene speed = scene;
      speed.render.colorBy = ColorBy::Speed;
      const Diff ramp = compare(renderDamBreak(tag + "_speed", speed, source), want);
      EXPECT_FALSE(withinThresholds(ramp)) << "speed ramp: " << ramp;
    } else {
      // Water missing: the stage alone, from an empty mesh.
      const std::string shot = test::tempDir("surface_empty");
      fs::create_directories(fs::path(meshPath(shot, kDamBreakFrame)).parent_path());
      writePly(meshPath(shot, kDamBreakFrame), TriangleMesh{});
      RenderShotOptions o;
      o.shotDir = shot;
      o.source = source;
      o.frames = FrameRange{kDamBreakFrame, kDamBreakFrame};
      renderShot(scene, o);
      const Diff empty = compare(readPng(renderPath(shot, "surface", kDamBreakFrame, "png")), want);
      EXPECT_FALSE(withinThresholds(empty)) << "no water: " << empty;
    }
  }
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
