#include "sphfx/core/collider_motion.h"

#include <cmath>
#include <numbers>

namespace sphfx {

Quat operator*(const Quat& a, const Quat& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Quat conjugate(const Quat& q) {
  return {q.w, -q.x, -q.y, -q.z};
}

Quat quatFromRotationVector(const Vec3d& r) {
  const double angle = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  if (angle < 1e-300) return {};
  const double s = std::sin(0.5 * angle) / angle;
  return {std::cos(0.5 * angle), r[0] * s, r[1] * s, r[2] * s};
}

Quat quatFromEulerDegrees(const Vec3d& d) {
  const double k = std::numbers::pi / 180.0;
  const Quat qx = quatFromRotationVector({d[0] * k, 0, 0}), qy = quatFromRotationVector({0, d[1] * k, 0}),
             qz = quatFromRotationVector({0, 0, d[2] * k});
  return qz * (qy * qx);
}

Vec3d rotate(const Quat& q, const Vec3d& v) {
  const Quat r = q * (Quat{0, v[0], v[1], v[2]} * conjugate(q));
  return {r.x, r.y, r.z};
}

Vec3d rotationVector(const Quat& q) {
  Quat s = q.w < 0 ? Quat{-q.w, -q.x, -q.y, -q.z} : q;  // the shortest arc
  const double sinHalf = std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
  if (sinHalf < 1e-300) return {0, 0, 0};
  const double angle = 2.0 * std::atan2(sinHalf, s.w);
  return {s.x / sinHalf * angle, s.y / sinHalf * angle, s.z / sinHalf * angle};
}

Vec3d colliderPivot(const Collider& c) {
  switch (c.shape) {
    case Shape::Box:
      return {0.5 * (c.min[0] + c.max[0]), 0.5 * (c.min[1] + c.max[1]), 0.5 * (c.min[2] + c.max[2])};
    case Shape::Sphere:
      return c.center;
    case Shape::Mesh:
    case Shape::Vdb:
      return c.translation;
  }
  return {0, 0, 0};
}

Vec3d ColliderPose::toWorld(const Vec3d& rest) const {
  const Vec3d r = rotate(rotation, {rest[0] - pivot[0], rest[1] - pivot[1], rest[2] - pivot[2]});
  return {pivot[0] + offset[0] + r[0], pivot[1] + offset[1] + r[1], pivot[2] + offset[2] + r[2]};
}

Vec3d ColliderPose::toRest(const Vec3d& world) const {
  const Vec3d d{world[0] - pivot[0] - offset[0], world[1] - pivot[1] - offset[1],
                world[2] - pivot[2] - offset[2]};
  const Vec3d r = rotate(conjugate(rotation), d);
  return {pivot[0] + r[0], pivot[1] + r[1], pivot[2] + r[2]};
}

Vec3d ColliderPose::velocityAt(const Vec3d& x) const {
  const Vec3d r{x[0] - pivot[0] - offset[0], x[1] - pivot[1] - offset[1], x[2] - pivot[2] - offset[2]};
  const Vec3d& w = angularVelocity;
  return {velocity[0] + w[1] * r[2] - w[2] * r[1], velocity[1] + w[2] * r[0] - w[0] * r[2],
          velocity[2] + w[0] * r[1] - w[1] * r[0]};
}

ColliderPose colliderPose(const Collider& c, double t) {
  ColliderPose pose;
  pose.pivot = colliderPivot(c);
  const auto& keys = c.keyframes;
  if (keys.empty()) return pose;
  auto hold = [&](const Keyframe& k) {
    pose.offset = k.offset;
    pose.rotation = quatFromEulerDegrees(k.rotation);
    return pose;
  };
  if (t <= keys.front().time) return hold(keys.front());
  for (size_t k = 1; k < keys.size(); ++k) {
    const Keyframe &a = keys[k - 1], &b = keys[k];
    if (!(t < b.time)) continue;
    const double span = b.time - a.time, s = (t - a.time) / span;
    const Quat qa = quatFromEulerDegrees(a.rotation), qb = quatFromEulerDegrees(b.rotation);
    const Vec3d arc = rotationVector(qb * conjugate(qa));
    for (int i = 0; i < 3; ++i) {
      pose.offset[i] = a.offset[i] + s * (b.offset[i] - a.offset[i]);
      pose.velocity[i] = (b.offset[i] - a.offset[i]) / span;
      pose.angularVelocity[i] = arc[i] / span;
    }
    pose.rotation = quatFromRotationVector({arc[0] * s, arc[1] * s, arc[2] * s}) * qa;
    return pose;
  }
  return hold(keys.back());
}

bool anyColliderRotates(const Scene& scene) {
  for (const Collider& c : scene.colliders)
    for (const Keyframe& k : c.keyframes)
      if (k.rotation[0] != 0 || k.rotation[1] != 0 || k.rotation[2] != 0) return true;
  return false;
}

}  // namespace sphfx
