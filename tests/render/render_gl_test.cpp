// GL image tests of the renderer: geometry lands where independent maths says, depth is right, and small
// frames match committed references. Run once per headless backend (SPHFX_GL).
#include <gtest/gtest.h>

#include <ImfFrameBuffer.h>
#include <ImfInputFile.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "../core/gpu_layout_check.h"
#include "gpu_layouts.h"
#include "render_shaders.h"
#include "render_test_util.h"

using namespace sphfx;
using namespace sphfx::render;

namespace {

class RenderGL : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ctx_ = test::makeContext(); }
  static void TearDownTestSuite() { ctx_.reset(); }
  static std::unique_ptr<GLContext> ctx_;
};
std::unique_ptr<GLContext> RenderGL::ctx_;

double alphaSum(const Image& img) {
  double s = 0;
  for (size_t i = 3; i < img.rgba.size(); i += 4) s += img.rgba[i];
  return s;
}

}  // namespace

TEST_F(RenderGL, BlocksMatchGlsl) {
  test::checkGpuLayouts(renderShaderTable(), renderGpuLayouts());
}

TEST_F(RenderGL, SphereCoverageMatchesProjectedDisc) {
  const int w = 320, h = 240;
  const double fov = 40, d = 5, radius = 1;
  Renderer renderer(w, h, 4);
  const Image img = renderer.renderSurface(makeUvSphere({0, 0, 0}, radius, 128, 256), test::emptyStage(),
                                           test::axisCamera(d, fov));
  // The silhouette of a sphere on the optical axis is a circle: the tangent cone's half angle is
  // asin(R/d), so its radius on the image plane is f * tan(asin(R/d)) pixels.
  const double fPixels = (h / 2.0) / std::tan(fov * M_PI / 360);
  const double rPixels = fPixels * std::tan(std::asin(radius / d));
  const double expected = M_PI * rPixels * rPixels;
  const double covered = alphaSum(img);
  EXPECT_NEAR(covered / expected, 1.0, 0.005) << "covered " << covered << " px, expected " << expected;
  // Centred: equal coverage in the left and right, top and bottom halves.
  double left = 0, top = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      left += x < w / 2 ? img.pixel(x, y)[3] : 0;
      top += y < h / 2 ? img.pixel(x, y)[3] : 0;
    }
  EXPECT_NEAR(left / covered, 0.5, 0.002);
  EXPECT_NEAR(top / covered, 0.5, 0.002);
  // The nearest point of the sphere, at the centre, is d - R away.
  EXPECT_NEAR(img.depth[size_t(h / 2) * w + w / 2], d - radius, 2e-3);
}

TEST_F(RenderGL, OrthographicBoxCoversExactPixelRectangle) {
  const int w = 64, h = 48;
  const double pixel = 0.1;
  CameraView cam = test::axisCamera(10, 40, 1, 20);
  cam.orthographic = true;
  cam.orthoHeight = h * pixel;
  Stage stage = test::emptyStage();
  // Box edges on pixel boundaries: columns 12..36, rows 6..21 from the top (the image is 6.4 x 4.8 m,
  // x from -3.2, y down from +2.4). Off-centre, so a flipped image fails.
  stage.solids.push_back({makeBox({-2.0, 0.3, -1}, {0.5, 1.8, 1}), {0, 0, 0}, {0.5f, 0.5f, 0.5f}});
  Renderer renderer(w, h, 4);
  const Image img = renderer.renderSurface({}, stage, cam);
  int wrong = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool inside = x >= 12 && x < 37 && y >= 6 && y < 21;
      const float a = img.pixel(x, y)[3];
      if (inside ? a < 0.999f : a > 0.001f) ++wrong;
      if (inside)
        EXPECT_NEAR(img.depth[size_t(y) * w + x], 9.0, 1e-4);
      else
        EXPECT_TRUE(std::isinf(img.depth[size_t(y) * w + x]));
    }
  EXPECT_EQ(wrong, 0);
}

TEST_F(RenderGL, ParticlesLandAtProjectedPixelsWithTrueDepth) {
  const int w = 320, h = 240;
  const double fov = 45, d = 5, r = 0.1;
  const double centres[][3] = {{-1, 0.5, 0}, {0.8, -0.4, -1}, {0.3, 0.6, 1}, {-0.2, -0.7, 0.5}};
  std::vector<ParticleInstance> ps;
  for (const auto& c : centres) ps.push_back({{float(c[0]), float(c[1]), float(c[2])}, 0});
  ParticleStyle style;
  style.radius = float(r);
  Renderer renderer(w, h, 4);
  const Image img = renderer.renderParticles(ps, style, test::emptyStage(), test::axisCamera(d, fov));
  for (const auto& c : centres) {
    const test::PixelPos p = test::projectAxis(c[0], c[1], c[2], d, fov, w, h);
    const int i = int(p.x), j = int(p.y);
    SCOPED_TRACE(testing::Message() << "particle at " << c[0] << "," << c[1] << "," << c[2] << " -> pixel "
                                    << i << "," << j);
    EXPECT_GT(img.pixel(i, j)[3], 0.999f);
    EXPECT_NEAR(img.depth[size_t(j) * w + i], test::rayDepth(i, j, c, r, d, fov, w, h), 1e-3);
    // Projected radius (pixels) and a ring just outside it that must be empty.
    const double rp = (h / 2.0) / std::tan(fov * M_PI / 360) * r / (d - c[2]);
    for (int k = 0; k < 8; ++k) {
      const double a = k * M_PI / 4;
      const int x = int(p.x + (rp + 2.5) * std::cos(a)), y = int(p.y + (rp + 2.5) * std::sin(a));
      EXPECT_EQ(img.pixel(x, y)[3], 0.f) << "outside the silhouette at " << x << "," << y;
      const int xi = int(p.x + (rp - 1.5) * std::cos(a)), yi = int(p.y + (rp - 1.5) * std::sin(a));
      EXPECT_GT(img.pixel(xi, yi)[3], 0.999f) << "inside the silhouette at " << xi << "," << yi;
    }
  }
}

TEST_F(RenderGL, NearerParticleWinsWhateverTheDrawOrder) {
  const int w = 160, h = 120;
  const double fov = 40, d = 4, r = 0.2;
  const double farC[3] = {0, 0, 0}, nearC[3] = {0.15, 0.05, 0.6};
  ParticleStyle style;
  style.radius = float(r);
  style.colorBy = ColorBy::Speed;
  style.speedScale = 1;
  const ParticleInstance slow{{0, 0, 0}, 0}, fast{{0.15f, 0.05f, 0.6f}, 1};  // dark blue, white
  Renderer renderer(w, h, 4);
  const Image a = renderer.renderParticles({slow, fast}, style, test::emptyStage(), test::axisCamera(d, fov));
  const Image b = renderer.renderParticles({fast, slow}, style, test::emptyStage(), test::axisCamera(d, fov));
  EXPECT_EQ(a.rgba, b.rgba);
  const test::PixelPos pn = test::projectAxis(nearC[0], nearC[1], nearC[2], d, fov, w, h);
  const int i = int(pn.x), j = int(pn.y);
  // The near (white) sphere covers the far one there: red channel high, and its depth, not the far one's.
  EXPECT_GT(a.pixel(i, j)[0], 0.4f);
  EXPECT_NEAR(a.depth[size_t(j) * w + i], test::rayDepth(i, j, nearC, r, d, fov, w, h), 1e-3);
  const test::PixelPos pf = test::projectAxis(-0.15, -0.05, 0, d, fov, w, h);  // far sphere only
  const int fi = int(pf.x), fj = int(pf.y);
  EXPECT_LT(a.pixel(fi, fj)[0], 0.1f);
  EXPECT_NEAR(a.depth[size_t(fj) * w + fi], test::rayDepth(fi, fj, farC, r, d, fov, w, h), 1e-3);

  // The EXR's Z channel, read back with OpenEXR itself, carries the same depths.
  const std::string path = test::tempDir("exr_depth") + "/z.exr";
  writeExr(path, a);
  Imf::InputFile file(path.c_str());
  std::vector<float> z(size_t(w) * h);
  Imf::FrameBuffer fb;
  fb.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(z.data()), sizeof(float), sizeof(float) * w));
  file.setFrameBuffer(fb);
  file.readPixels(0, h - 1);
  EXPECT_NEAR(z[size_t(j) * w + i], test::rayDepth(i, j, nearC, r, d, fov, w, h), 1e-3);
  EXPECT_TRUE(std::isinf(z[0]));
}

// Point-sprite impostors (with their occluder pass and occlusion cull) against a brute-force CPU ray cast:
// a jittered block of touching spheres, several rows deep, plus spheres straddling the image's left and
// bottom edges (the quad fallback) and one behind the camera (dropped). Every pixel whose ray is not
// within a hair of some sphere's silhouette must be covered exactly when the CPU ray hits a sphere, with
// the CPU's nearest depth.
TEST_F(RenderGL, PointImpostorsMatchCpuRayCast) {
  const int w = 160, h = 120;
  const double fov = 40, d = 3, r = 0.05;
  std::vector<ParticleInstance> ps;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.2 * r, 0.2 * r);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      for (int k = 0; k < 8; ++k)
        ps.push_back({{float(-0.35 + 2 * r * i + jitter(rng)), float(-0.35 + 2 * r * j + jitter(rng)),
                       float(-0.35 + 2 * r * k + jitter(rng))},
                      0});
  // Half a pixel outside the left edge and the bottom edge at depth d (f pixels per unit at unit depth).
  const double f = (h / 2.0) / std::tan(fov * M_PI / 360);
  const double xEdge = (w / 2.0 + 0.5) / f * d, yEdge = (h / 2.0 + 0.5) / f * d;
  ps.push_back({{float(-xEdge), 0.f, 0.f}, 0});
  ps.push_back({{0.f, float(-yEdge), 0.f}, 0});
  ps.push_back({{0.f, 0.f, float(d + 1)}, 0});  // behind the camera
  ParticleStyle style;
  style.radius = float(r);
  Renderer renderer(w, h, 4);
  const Image img = renderer.renderParticles(ps, style, test::emptyStage(), test::axisCamera(d, fov));
  const Renderer::ParticleCounts counts = renderer.lastParticleCounts();
  EXPECT_EQ(counts.quads, 2u) << "the two edge spheres";
  EXPECT_EQ(counts.culled, 1u) << "the sphere behind the camera";
  EXPECT_EQ(counts.points, 512u);
  EXPECT_LT(counts.visible, counts.points) << "the occlusion cull drops the hidden rows";

  int checked = 0, coverageErrors = 0, depthErrors = 0;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      double nearest = INFINITY;
      bool grazing = false;
      for (const ParticleInstance& p : ps) {
        const double c[3] = {p.position[0], p.position[1], p.position[2]};
        // Grazing: the ray passes within 0.2 % of r of the silhouette; rounding may go either way.
        const bool inner = !std::isnan(test::rayDepth(i, j, c, r * 0.998, d, fov, w, h));
        const bool outer = !std::isnan(test::rayDepth(i, j, c, r * 1.002, d, fov, w, h));
        grazing = grazing || inner != outer;
        const double t = test::rayDepth(i, j, c, r, d, fov, w, h);
        if (t > 0) nearest = std::min(nearest, t);
      }
      if (grazing) continue;
      ++checked;
      const bool covered = img.pixel(i, j)[3] > 0.5f;
      if (covered != std::isfinite(nearest)) {
        ++coverageErrors;
        ADD_FAILURE() << "pixel " << i << "," << j << ": covered " << covered << ", CPU nearest " << nearest;
      } else if (covered && std::abs(img.depth[size_t(j) * w + i] - nearest) > 1e-3) {
        ++depthErrors;
        ADD_FAILURE() << "pixel " << i << "," << j << ": depth " << img.depth[size_t(j) * w + i] << ", CPU "
                      << nearest;
      }
      if (coverageErrors + depthErrors > 20) return;
    }
  EXPECT_GT(checked, w * h * 9 / 10);
  // The edge spheres are drawn (quad path): the CPU sees them in column 0 and row h-1.
  EXPECT_GT(img.pixel(0, h / 2)[3], 0.5f);
  EXPECT_GT(img.pixel(w / 2, h - 1)[3], 0.5f);
}

// Orthographic camera: point impostors are discs of radius r / pixel size with the ray origin on the near
// plane, and the depth at the centre is the distance to the sphere's front.
TEST_F(RenderGL, OrthographicPointImpostorIsAnExactDisc) {
  const int w = 64, h = 48;
  const double pixel = 0.1, r = 0.8;  // 8 px radius
  CameraView cam = test::axisCamera(10, 40, 1, 20);
  cam.orthographic = true;
  cam.orthoHeight = h * pixel;
  ParticleStyle style;
  style.radius = float(r);
  Renderer renderer(w, h, 4);
  // Off-centre by whole pixels: centre at pixel boundary (40, 20) from the top-left.
  const Image img = renderer.renderParticles({{{0.8f, 0.4f, 0.f}, 0}}, style, test::emptyStage(), cam);
  EXPECT_EQ(renderer.lastParticleCounts().points, 1u);
  int wrong = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double dx = (x + 0.5 - 40) * pixel, dy = (y + 0.5 - 20) * pixel;
      const double rho2 = dx * dx + dy * dy;
      if (std::abs(std::sqrt(rho2) - r) < 0.01) continue;  // on the silhouette: rounding decides
      const bool inside = rho2 < r * r;
      if (inside != (img.pixel(x, y)[3] > 0.5f)) ++wrong;
      if (inside) {
        EXPECT_NEAR(img.depth[size_t(y) * w + x], 10 - std::sqrt(r * r - rho2), 1e-4);
      }
    }
  EXPECT_EQ(wrong, 0);
}
