#pragma once
// Helpers of the render tests: a GL context for the backend CI picks (SPHFX_GL), and independent
// (test-side) camera maths, so that the renderer's matrices are checked against a second derivation.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "../common/scratch_dir.h"
#include "renderer.h"
#include "sphfx/gpu/gl_context.h"

namespace sphfx::test {

inline std::unique_ptr<GLContext> makeContext() {
  const char* name = std::getenv("SPHFX_GL");
  return GLContext::create({parseGLBackend(name ? name : "auto"), false});
}

inline std::string tempDir(const std::string& name) {
  const auto dir = scratchPath("render_test_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

/// A stage with nothing but the object under test (no sky, ground or walls).
inline render::Stage emptyStage() {
  render::Stage s;
  s.sky = s.ground = s.walls = false;
  s.domain = {{-1, -1, -1}, {1, 1, 1}};
  return s;
}

/// A camera on the +Z axis at distance `d` looking at the origin: view space is world space shifted by -d
/// along z, which the tests use for their own projection.
inline render::CameraView axisCamera(double d, double fovDeg, double nearPlane = 0.5, double farPlane = 20) {
  render::CameraView c;
  c.position = {0, 0, d};
  c.lookAt = {0, 0, 0};
  c.fovYDegrees = fovDeg;
  c.nearPlane = nearPlane;
  c.farPlane = farPlane;
  return c;
}

/// Pixel coordinates (x right, y down from the top, continuous: pixel i covers [i, i+1)) of a world point
/// seen by axisCamera(d, fov) in a w x h image.
struct PixelPos {
  double x, y;
};
inline PixelPos projectAxis(double px, double py, double pz, double d, double fovDeg, int w, int h) {
  const double f = 1 / std::tan(fovDeg * M_PI / 360);  // focal length in NDC units (vertical)
  const double depth = d - pz;
  const double aspect = double(w) / h;
  const double xn = px / depth * f / aspect, yn = py / depth * f;
  return {(xn * 0.5 + 0.5) * w, (0.5 - yn * 0.5) * h};
}

/// View-axis depth where the ray of axisCamera through the centre of pixel (i, j) first hits the sphere
/// (c, r), or NaN on a miss.
inline double rayDepth(int i, int j, const double c[3], double r, double d, double fovDeg, int w, int h) {
  const double f = 1 / std::tan(fovDeg * M_PI / 360), aspect = double(w) / h;
  const double xn = ((i + 0.5) / w) * 2 - 1, yn = 1 - ((j + 0.5) / h) * 2;
  double dir[3] = {xn * aspect / f, yn / f, -1};  // unit depth along the view axis
  const double o[3] = {0, 0, d};
  double oc[3] = {o[0] - c[0], o[1] - c[1], o[2] - c[2]};
  const double a = dir[0] * dir[0] + dir[1] * dir[1] + 1;
  const double b = oc[0] * dir[0] + oc[1] * dir[1] + oc[2] * dir[2];
  const double cc = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - r * r;
  const double disc = b * b - a * cc;
  if (disc < 0) return NAN;
  return (-b - std::sqrt(disc)) / a;  // dir has unit view-axis component, so t is the depth
}

}  // namespace sphfx::test
