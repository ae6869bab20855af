// GL image tests of the renderer: geometry lands where independent maths says, depth is right, and small
// frames match committed references. Run once per headless backend (SPHFX_GL).
#include <gtest/gtest.h>

#include <ImfFrameBuffer.h>
#include <ImfInputFile.h>

#include <cmath>
#include <filesystem>

#include "../core/gpu_layout_check.h"
#include "render_test_util.h"
#include "sphfx/render/gpu_layouts.h"

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
  test::checkGpuLayouts(renderGpuLayouts());
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
