#pragma once
/// @file collider_motion.h
/// @brief Rigid motion of colliders: the pose (translation and rotation about the pivot) and velocities
/// at a time, from the collider's keyframes. One definition shared by the simulation (which uploads the
/// per-segment velocities), the renderer and the physical checks.

#include <array>

#include "sphfx/core/scene.h"

namespace sphfx {

/// Unit quaternion w + xi + yj + zk.
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

Quat operator*(const Quat& a, const Quat& b);
Quat conjugate(const Quat& q);
/// Rotation by |axisAngle| radians about axisAngle's direction.
Quat quatFromRotationVector(const Vec3d& axisAngle);
/// Degrees about the fixed x, then y, then z axes (R = Rz Ry Rx), the scenes' rotation convention.
Quat quatFromEulerDegrees(const Vec3d& degrees);
Vec3d rotate(const Quat& q, const Vec3d& v);
/// The rotation vector (axis times angle, radians, angle in [0, pi]) of q's shortest arc.
Vec3d rotationVector(const Quat& q);

/// The point collider rotations turn about, at rest: a box's or sphere's centre, a mesh's or vdb's
/// origin after placement (its translation), as a TD's object pivot.
Vec3d colliderPivot(const Collider& collider);

/// Where a collider is and how it moves at time t. Between keys k and k+1 the translation is linear and
/// the rotation turns at the constant angular velocity of the shortest arc from q_k to q_{k+1}
/// (quaternion slerp); before the first and after the last key the collider is held at rest there.
struct ColliderPose {
  Vec3d pivot{};            ///< rest pivot
  Vec3d offset{};           ///< translation of the pivot
  Quat rotation;            ///< about the pivot
  Vec3d velocity{};         ///< of the pivot (m/s)
  Vec3d angularVelocity{};  ///< world frame (rad/s)

  /// The world position of a point given in the rest placement.
  Vec3d toWorld(const Vec3d& rest) const;
  /// The rest-placement position of a world point.
  Vec3d toRest(const Vec3d& world) const;
  /// The velocity of the body's material at world point x: v + omega x (x - pivot - offset).
  Vec3d velocityAt(const Vec3d& world) const;
};

ColliderPose colliderPose(const Collider& collider, double time);

/// True if any key of any collider rotates it.
bool anyColliderRotates(const Scene& scene);

}  // namespace sphfx
