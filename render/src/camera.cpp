#include "camera.h"

#include <algorithm>
#include <cmath>

#include "sphfx/core/collider_motion.h"
#include "sphfx/core/error.h"

namespace sphfx::render {

Mat4 identity() {
  return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
}

Mat4 multiply(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + row] * b[c * 4 + k];
      r[c * 4 + row] = s;
    }
  return r;
}

Mat4 inverse(const Mat4& m) {
  // Gauss-Jordan with partial pivoting on a row-major copy [m | I].
  double a[4][8];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      a[r][c] = m[c * 4 + r];
      a[r][c + 4] = r == c ? 1 : 0;
    }
  for (int col = 0; col < 4; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 4; ++r)
      if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
    if (std::abs(a[pivot][col]) < 1e-300) throw InputError("render: singular camera matrix");
    std::swap(a[pivot], a[col]);
    const double inv = 1 / a[col][col];
    for (double& v : a[col]) v *= inv;
    for (int r = 0; r < 4; ++r) {
      if (r == col) continue;
      const double f = a[r][col];
      for (int c = 0; c < 8; ++c) a[r][c] -= f * a[col][c];
    }
  }
  Mat4 out{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[c * 4 + r] = a[r][c + 4];
  return out;
}

Vec3d transformPoint(const Mat4& m, const Vec3d& p) {
  double o[4];
  for (int r = 0; r < 4; ++r) o[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
  return {o[0] / o[3], o[1] / o[3], o[2] / o[3]};
}

Mat4 translation(const Vec3d& t) {
  Mat4 m = identity();
  m[12] = t[0], m[13] = t[1], m[14] = t[2];
  return m;
}

Vec3d add(const Vec3d& a, const Vec3d& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec3d sub(const Vec3d& a, const Vec3d& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3d scale(const Vec3d& a, double s) {
  return {a[0] * s, a[1] * s, a[2] * s};
}
double dot(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3d cross(const Vec3d& a, const Vec3d& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double length(const Vec3d& a) {
  return std::sqrt(dot(a, a));
}
Vec3d normalize(const Vec3d& a) {
  const double l = length(a);
  if (!(l > 0)) throw InputError("render: cannot normalise a zero vector (camera on its look-at point?)");
  return scale(a, 1 / l);
}

CameraBasis cameraBasis(const CameraView& camera) {
  const Vec3d forward = normalize(sub(camera.lookAt, camera.position));
  const Vec3d side = cross(forward, camera.up);
  if (length(side) < 1e-9) throw InputError("render: camera view direction is parallel to its up vector");
  const Vec3d right = normalize(side);
  return {right, cross(right, forward), forward};
}

Mat4 viewMatrix(const CameraView& camera) {
  const CameraBasis b = cameraBasis(camera);
  const Vec3d& e = camera.position;
  return {b.right[0],       b.up[0],       -b.forward[0],     0,  //
          b.right[1],       b.up[1],       -b.forward[1],     0,  //
          b.right[2],       b.up[2],       -b.forward[2],     0,  //
          -dot(b.right, e), -dot(b.up, e), dot(b.forward, e), 1};
}

Mat4 projectionMatrix(const CameraView& camera, double aspect) {
  const double n = camera.nearPlane, f = camera.farPlane;
  if (!(aspect > 0) || !(f > n) || (!camera.orthographic && !(n > 0)))
    throw InputError("render: invalid projection (need aspect > 0, 0 < near < far)");
  Mat4 p{};
  if (camera.orthographic) {
    const double h = camera.orthoHeight / 2, w = h * aspect;
    p[0] = 1 / w, p[5] = 1 / h, p[10] = -2 / (f - n), p[14] = -(f + n) / (f - n), p[15] = 1;
  } else {
    const double t = 1 / std::tan(camera.fovYDegrees * M_PI / 360);
    p[0] = t / aspect, p[5] = t, p[10] = -(f + n) / (f - n), p[11] = -1, p[14] = -2 * f * n / (f - n);
  }
  return p;
}

namespace {

template <class Key, class Get>
Vec3d interpolateKeys(const std::vector<Key>& keys, double time, Get get) {
  // Keys may come in any order in the file; interpolate over them sorted by time.
  std::vector<const Key*> sorted;
  for (const Key& k : keys) sorted.push_back(&k);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const Key* a, const Key* b) { return a->time < b->time; });
  if (time <= sorted.front()->time) return get(*sorted.front());
  for (size_t i = 1; i < sorted.size(); ++i) {
    const Key& a = *sorted[i - 1];
    const Key& b = *sorted[i];
    if (time <= b.time) {
      const double s = b.time > a.time ? (time - a.time) / (b.time - a.time) : 1;
      return add(scale(get(a), 1 - s), scale(get(b), s));
    }
  }
  return get(*sorted.back());
}

/// Near/far that enclose a sphere (the domain and the ground around it) seen from `eye`.
void fitClipPlanes(CameraView& view, const Vec3d& center, double radius) {
  const double d = length(sub(center, view.position));
  view.farPlane = d + radius;
  view.nearPlane = std::max(d - radius, view.farPlane * 1e-4);
}

}  // namespace

Vec3d colliderOffset(const Collider& collider, double time) {
  return colliderPose(collider, time).offset;
}

CameraView sceneCamera(const Scene& scene, double time, double aspect) {
  const Domain& d = scene.domain;
  const Vec3d center = scale(add(d.min, d.max), 0.5);
  const double radius = length(sub(d.max, d.min)) / 2;
  CameraView view;
  if (scene.render.camera) {
    const Camera& c = *scene.render.camera;
    view.fovYDegrees = c.fovDegrees;
    view.position = c.position;
    view.lookAt = c.lookAt;
    if (!c.keyframes.empty()) {
      view.position = interpolateKeys(c.keyframes, time, [](const CameraKey& k) { return k.position; });
      view.lookAt = interpolateKeys(c.keyframes, time, [](const CameraKey& k) { return k.lookAt; });
    }
  } else {
    // Three-quarter view from front-right and above, far enough that the domain's bounding sphere fits
    // the narrower of the two fields of view.
    view.fovYDegrees = 40;
    const double halfY = view.fovYDegrees * M_PI / 360;
    const double half = std::min(halfY, std::atan(aspect * std::tan(halfY)));
    const Vec3d dir = normalize({0.75, 0.55, 1.3});
    view.lookAt = {center[0], d.min[1] + (d.max[1] - d.min[1]) * 0.4, center[2]};
    view.position = add(view.lookAt, scale(dir, radius / std::sin(half)));
  }
  if (std::abs(dot(normalize(sub(view.lookAt, view.position)), {0, 1, 0})) > 0.999999) view.up = {0, 0, -1};
  // The ground extends well beyond the domain; keep it within the far plane.
  fitClipPlanes(view, center, radius * 12);
  return view;
}

}  // namespace sphfx::render
