// Camera maths and shot option parsing (no GL).
#include <gtest/gtest.h>

#include <cmath>

#include "camera.h"
#include "sphfx/core/error.h"
#include "sphfx/render/render_shot.h"

using namespace sphfx;
using namespace sphfx::render;

TEST(Camera, PerspectiveMapsLookAtToCentreAndFrustumEdgeToNdcOne) {
  CameraView c;
  c.position = {1, 2, 3};
  c.lookAt = {1, 2, -7};
  c.fovYDegrees = 60;
  c.nearPlane = 1, c.farPlane = 100;
  const Mat4 vp = multiply(projectionMatrix(c, 2.0), viewMatrix(c));
  const Vec3d centre = transformPoint(vp, c.lookAt);
  EXPECT_NEAR(centre[0], 0, 1e-12);
  EXPECT_NEAR(centre[1], 0, 1e-12);
  // A point at depth 10 and height 10 tan(30 deg) sits on the top edge; 2x that sideways on the right edge.
  const double t = 10 * std::tan(M_PI / 6);
  const Vec3d edge = transformPoint(vp, {1 + 2 * t, 2 + t, -7});
  EXPECT_NEAR(edge[0], 1, 1e-12);
  EXPECT_NEAR(edge[1], 1, 1e-12);
  EXPECT_NEAR(transformPoint(vp, {1, 2, 2})[2], -1, 1e-12);   // near plane
  EXPECT_NEAR(transformPoint(vp, {1, 2, -97})[2], 1, 1e-12);  // far plane
}

TEST(Camera, InverseUndoesViewProjection) {
  CameraView c;
  c.position = {2, 1.5, 3};
  c.lookAt = {0.5, 0.3, 0.5};
  const Mat4 vp = multiply(projectionMatrix(c, 16.0 / 9), viewMatrix(c));
  const Mat4 id = multiply(inverse(vp), vp);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(id[i], i % 5 == 0 ? 1 : 0, 1e-9);
}

TEST(Camera, BadCamerasThrow) {
  CameraView c;
  c.lookAt = c.position;
  EXPECT_THROW(viewMatrix(c), InputError);
  c.lookAt = {0, 5, 5};  // straight up along the up vector
  EXPECT_THROW(viewMatrix(c), InputError);
  CameraView p;
  p.nearPlane = 0;
  EXPECT_THROW(projectionMatrix(p, 1), InputError);
}

TEST(Camera, KeyframesInterpolateLinearlyAndHold) {
  Collider col;
  col.keyframes = {{0.0, {2, 0, 0}}, {1.0, {0, 0, 0}}, {3.0, {0, 4, 0}}};  // scenes hold keys in time order
  EXPECT_EQ(colliderOffset(col, -1)[0], 2);
  EXPECT_NEAR(colliderOffset(col, 0.25)[0], 1.5, 1e-12);
  EXPECT_NEAR(colliderOffset(col, 2)[1], 2, 1e-12);
  EXPECT_EQ(colliderOffset(col, 10)[1], 4);
  EXPECT_EQ(colliderOffset(Collider{}, 1)[0], 0);

  Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json");
  scene.render.camera->keyframes = {{0, {0, 1, 2}, {0, 0, 0}}, {1, {2, 1, 2}, {1, 0, 0}}};
  const CameraView v = sceneCamera(scene, 0.5, 16.0 / 9);
  EXPECT_NEAR(v.position[0], 1, 1e-12);
  EXPECT_NEAR(v.lookAt[0], 0.5, 1e-12);
}

TEST(Camera, AutomaticFramingSeesTheWholeDomain) {
  Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json");
  scene.render.camera.reset();
  for (double aspect : {16.0 / 9, 1.0, 0.5}) {
    const CameraView v = sceneCamera(scene, 0, aspect);
    const Mat4 vp = multiply(projectionMatrix(v, aspect), viewMatrix(v));
    for (int k = 0; k < 8; ++k) {
      const Vec3d corner{(k & 1) ? scene.domain.max[0] : scene.domain.min[0],
                         (k & 2) ? scene.domain.max[1] : scene.domain.min[1],
                         (k & 4) ? scene.domain.max[2] : scene.domain.min[2]};
      const Vec3d ndc = transformPoint(vp, corner);
      for (int a = 0; a < 3; ++a) EXPECT_LT(std::abs(ndc[a]), 1.0) << "aspect " << aspect << " corner " << k;
    }
  }
}

TEST(ShotOptions, ImageSize) {
  EXPECT_EQ(parseImageSize("1920x1080"), std::make_pair(1920, 1080));
  for (const char* bad : {"1920", "1920x", "x1080", "1920x1080x", "8x8", "1920*1080", "-5x100"})
    EXPECT_THROW(parseImageSize(bad), InputError) << bad;
}
