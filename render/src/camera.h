#pragma once
/// @file camera.h
/// @brief Camera maths of the render stage: column-major 4x4 matrices (OpenGL conventions), the view of a
/// frame (from the scene's camera, its keyframes, or an automatic framing of the domain), and the
/// keyframed placement of colliders. Pure CPU code, no GL.

#include <array>
#include <vector>

#include "sphfx/core/scene.h"

namespace sphfx::render {

/// Column-major 4x4 matrix: m[col * 4 + row], as glUniformMatrix4fv(..., GL_FALSE, ...) expects.
using Mat4 = std::array<double, 16>;

Mat4 identity();
Mat4 multiply(const Mat4& a, const Mat4& b);
/// General inverse. @throws InputError if the matrix is singular.
Mat4 inverse(const Mat4& m);
/// Transforms a point (w = 1) and divides by w.
Vec3d transformPoint(const Mat4& m, const Vec3d& p);
Mat4 translation(const Vec3d& t);

Vec3d add(const Vec3d& a, const Vec3d& b);
Vec3d sub(const Vec3d& a, const Vec3d& b);
Vec3d scale(const Vec3d& a, double s);
double dot(const Vec3d& a, const Vec3d& b);
Vec3d cross(const Vec3d& a, const Vec3d& b);
double length(const Vec3d& a);
/// a / |a|. @throws InputError for a zero vector.
Vec3d normalize(const Vec3d& a);

/// A camera for one frame. Perspective by default; orthographic (parallel rays along the view
/// direction, `orthoHeight` metres tall) when `orthographic` is set.
struct CameraView {
  Vec3d position{0, 0, 5};
  Vec3d lookAt{0, 0, 0};
  Vec3d up{0, 1, 0};  ///< world up hint; the true up is made perpendicular to the view direction
  double fovYDegrees = 40;
  bool orthographic = false;
  double orthoHeight = 2;
  double nearPlane = 0.05;
  double farPlane = 100;
};

/// World to camera (right-handed, camera looks down -Z). @throws InputError if position == lookAt or the
/// view direction is parallel to `up`.
Mat4 viewMatrix(const CameraView& camera);
/// Camera to clip space for an image of aspect width/height. @throws InputError for near >= far, near <= 0
/// (perspective) or a non-positive aspect.
Mat4 projectionMatrix(const CameraView& camera, double aspect);

/// Camera basis in world space: right, true up, and forward (the direction the camera looks).
struct CameraBasis {
  Vec3d right, up, forward;
};
/// @throws InputError as viewMatrix().
CameraBasis cameraBasis(const CameraView& camera);

/// The scene's camera at `time` seconds (keyframes linear in between, held outside), or an automatic
/// framing of the domain (three-quarter view from the front-right, above) when the scene has none. Near
/// and far planes are chosen to enclose the domain and the ground around it.
/// @throws InputError if the camera sits on its look-at point.
CameraView sceneCamera(const Scene& scene, double time, double aspect);

/// Translation of a collider at `time` (linear between keys, held outside them; zero without keys).
Vec3d colliderOffset(const Collider& collider, double time);

}  // namespace sphfx::render
