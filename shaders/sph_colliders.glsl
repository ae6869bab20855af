// Colliders: shapes at rest plus keyframed rigid motion. C++ mirror: sphfx::sim::ColliderGpu; the
// motion is sphfx::colliderPose() (core/collider_motion.h), which fills the key table.
struct SimCollider {
  vec4 shapeA;  // box: min corner; sphere: centre, w = radius; field: voxel (0,0,0)'s centre, w = voxel
  vec4 shapeB;  // box: max corner; field: voxel counts
  vec4 pivot;   // xyz: the rest pivot rotations turn about
  uvec4 info;   // x: 0 box / 1 sphere / 2 field, y: first key, z: key count, w: field's first value
};
layout(std430, binding = SPHFX_SSBO_SIM_COLLIDERS) readonly buffer SimColliders { SimCollider colliders[]; };
// Three per key: (time, offset from the rest placement), the rotation quaternion (xyzw), the angular
// velocity (rad/s, world) of the segment that starts at the key.
layout(std430, binding = SPHFX_SSBO_SIM_COLLIDER_KEYS) readonly buffer SimColliderKeys { vec4 colliderKeys[]; };
#if defined(HAS_FIELD_COLLIDERS)
layout(std430, binding = SPHFX_SSBO_SIM_COLLIDER_FIELD) readonly buffer SimColliderField { float colliderField[]; };
#endif

struct SphColliderPose {
  vec3 offset;    // translation of the pivot
  vec4 rotation;  // about the pivot, xyzw
  vec3 velocity;  // of the pivot
  vec3 omega;     // angular velocity
};

vec4 sphQuatMul(vec4 a, vec4 b) {
  return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}
vec3 sphQuatRotate(vec4 q, vec3 v) {
  vec3 t = 2.0 * cross(q.xyz, v);
  return v + q.w * t + cross(q.xyz, t);
}
vec4 sphQuatFromRotationVector(vec3 r) {
  float angle = length(r);
  return angle < 1e-30 ? vec4(0, 0, 0, 1) : vec4(r * (sin(0.5 * angle) / angle), cos(0.5 * angle));
}

// Pose of collider c at time t: linear translation and constant-rate rotation between keys, held
// outside them.
SphColliderPose sphColliderPose(uint c, float t) {
  SphColliderPose p = SphColliderPose(vec3(0.0), vec4(0, 0, 0, 1), vec3(0.0), vec3(0.0));
  uint first = colliders[c].info.y, n = colliders[c].info.z;
  if (n == 0u) return p;
  uint k0 = 3u * first;
  p.offset = colliderKeys[k0].yzw;
  p.rotation = colliderKeys[k0 + 1u];
  if (t <= colliderKeys[k0].x) return p;
  for (uint k = 1u; k < n; ++k) {
    uint k1 = 3u * (first + k);
    if (t < colliderKeys[k1].x) {
      float span = colliderKeys[k1].x - colliderKeys[k0].x, since = t - colliderKeys[k0].x;
      p.offset = mix(colliderKeys[k0].yzw, colliderKeys[k1].yzw, since / span);
      p.velocity = (colliderKeys[k1].yzw - colliderKeys[k0].yzw) / span;
#if defined(SIM_COLLIDER_ROTATION)
      p.omega = colliderKeys[k0 + 2u].xyz;
      p.rotation = sphQuatMul(sphQuatFromRotationVector(p.omega * since), colliderKeys[k0 + 1u]);
#endif
      return p;
    }
    k0 = k1;
    p.offset = colliderKeys[k0].yzw;
    p.rotation = colliderKeys[k0 + 1u];
  }
  return p;
}

// World point -> rest placement of collider c, and back; without rotating colliders, a translation.
vec3 sphColliderToRest(uint c, SphColliderPose p, vec3 x) {
#if defined(SIM_COLLIDER_ROTATION)
  vec3 pivot = colliders[c].pivot.xyz;
  return pivot + sphQuatRotate(vec4(-p.rotation.xyz, p.rotation.w), x - pivot - p.offset);
#else
  return x - p.offset;
#endif
}
vec3 sphColliderToWorld(uint c, SphColliderPose p, vec3 r) {
#if defined(SIM_COLLIDER_ROTATION)
  vec3 pivot = colliders[c].pivot.xyz;
  return pivot + p.offset + sphQuatRotate(p.rotation, r - pivot);
#else
  return r + p.offset;
#endif
}
vec3 sphColliderDirectionToWorld(SphColliderPose p, vec3 n) {
#if defined(SIM_COLLIDER_ROTATION)
  return sphQuatRotate(p.rotation, n);
#else
  return n;
#endif
}
// Velocity of the body's material at world point x: v + omega x r.
vec3 sphColliderVelocityAt(uint c, SphColliderPose p, vec3 x) {
#if defined(SIM_COLLIDER_ROTATION)
  return p.velocity + cross(p.omega, x - colliders[c].pivot.xyz - p.offset);
#else
  return p.velocity;
#endif
}

#if defined(HAS_FIELD_COLLIDERS)
// Trilinear signed distance of field collider c at rest-frame point r and its gradient direction
// (outward). Outside the voxel block: the distance to the block added, pointing away from it.
float sphFieldDistance(uint c, vec3 r, out vec3 normal) {
  SimCollider f = colliders[c];
  vec3 g = (r - f.shapeA.xyz) / f.shapeA.w, dims = f.shapeB.xyz;
  vec3 cl = clamp(g, vec3(0.0), dims - 1.0);
  ivec3 i0 = min(ivec3(cl), ivec3(dims) - 2);
  vec3 t = cl - vec3(i0);
  uint nx = uint(dims.x), nxy = nx * uint(dims.y);
  uint base = f.info.w + uint(i0.z) * nxy + uint(i0.y) * nx + uint(i0.x);
  float c000 = colliderField[base], c100 = colliderField[base + 1u];
  float c010 = colliderField[base + nx], c110 = colliderField[base + nx + 1u];
  float c001 = colliderField[base + nxy], c101 = colliderField[base + nxy + 1u];
  float c011 = colliderField[base + nxy + nx], c111 = colliderField[base + nxy + nx + 1u];
  float d = mix(mix(mix(c000, c100, t.x), mix(c010, c110, t.x), t.y),
                mix(mix(c001, c101, t.x), mix(c011, c111, t.x), t.y), t.z);
  vec3 grad = vec3(mix(mix(c100 - c000, c110 - c010, t.y), mix(c101 - c001, c111 - c011, t.y), t.z),
                   mix(mix(c010 - c000, c110 - c100, t.x), mix(c011 - c001, c111 - c101, t.x), t.z),
                   mix(mix(c001 - c000, c101 - c100, t.x), mix(c011 - c010, c111 - c110, t.x), t.y));
  vec3 away = g - cl;
  float outside = length(away);
  if (outside > 0.0) grad = away;
  float len = length(grad);
  normal = len > 1e-20 ? grad / len : vec3(0, 1, 0);
  return d + outside * f.shapeA.w;
}
#endif

// Whether world point x lies inside collider c placed at pose p (its surface counts as outside).
bool sphInsideCollider(uint c, SphColliderPose p, vec3 x) {
  vec3 r = sphColliderToRest(c, p, x);
  uint shape = colliders[c].info.x;
  if (shape == 0u)
    return all(greaterThan(r, colliders[c].shapeA.xyz)) && all(lessThan(r, colliders[c].shapeB.xyz));
  if (shape == 1u) return length(r - colliders[c].shapeA.xyz) < colliders[c].shapeA.w;
#if defined(HAS_FIELD_COLLIDERS)
  vec3 n;
  return sphFieldDistance(c, r, n) < 0.0;
#else
  return false;
#endif
}

// Signed distance (m; < 0 inside) from world point x to the surface of collider c placed at pose p, and
// the outward normal (world) there: exact for boxes and spheres, the trilinear field for mesh and vdb
// colliders (1e30 without field colliders compiled in).
float sphColliderDistance(uint c, SphColliderPose p, vec3 x, out vec3 normal) {
  vec3 r = sphColliderToRest(c, p, x), n = vec3(0, 1, 0);
  float d = 1e30;
  uint shape = colliders[c].info.x;
  if (shape == 0u) {
    vec3 centre = 0.5 * (colliders[c].shapeA.xyz + colliders[c].shapeB.xyz);
    vec3 side = mix(vec3(-1.0), vec3(1.0), greaterThanEqual(r, centre));
    vec3 q = abs(r - centre) - 0.5 * (colliders[c].shapeB.xyz - colliders[c].shapeA.xyz);
    vec3 beyond = max(q, vec3(0.0));
    float outside = length(beyond);
    if (outside > 0.0) {
      d = outside;
      n = side * beyond / outside;
    } else {  // inside: the nearest face
      int k = q.x >= q.y ? (q.x >= q.z ? 0 : 2) : (q.y >= q.z ? 1 : 2);
      d = q[k];
      n = vec3(0.0);
      n[k] = side[k];
    }
  } else if (shape == 1u) {
    vec3 offset = r - colliders[c].shapeA.xyz;
    float len = length(offset);
    d = len - colliders[c].shapeA.w;
    if (len > 1e-12) n = offset / len;
  }
#if defined(HAS_FIELD_COLLIDERS)
  else {
    d = sphFieldDistance(c, r, n);
  }
#endif
  normal = sphColliderDirectionToWorld(p, n);
  return d;
}

#if defined(SIM_COLLIDER_CONTACT)
// fluid.wall_contact on colliders, by distance and for every particle: the nearest collider surface to
// world point x at time t as sphWallContact() (sph_kernels.glsl) takes a constraint: xyz = grad = -n
// (into the collider), w = excess = SIM_COLLIDER_CONTACT (half a spacing, where a resting particle
// sits) less the distance; `rate` = the surface's velocity along grad. The walls' kernel sum cannot do
// this at colliders: near a convex edge it is smaller than a flat face's (fewer samples within h), and a
// sheet running over an edge keeps enough neighbours to count as bulk. A resting particle (no approach)
// never meets it.
vec4 sphColliderContact(vec3 x, float t, out float rate) {
  vec4 contact = vec4(0.0, -1.0, 0.0, -1e30);
  rate = 0.0;
  for (uint c = 0u; c < simCounts.z; ++c) {
    SphColliderPose p = sphColliderPose(c, t);
    vec3 n;
    float excess = SIM_COLLIDER_CONTACT - sphColliderDistance(c, p, x, n);
    if (excess <= contact.w) continue;
    contact = vec4(-n, excess);
    rate = -dot(sphColliderVelocityAt(c, p, x), n);
  }
  return contact;
}
#endif

// Pushes a particle at x out of collider c (placed for time t) to `margin` outside its surface, along the
// surface's normal (sphColliderDistance()), and removes the velocity component into the collider relative
// to the body's velocity there.
void sphProjectOutOfCollider(uint c, float t, float margin, inout vec3 x, inout vec3 v) {
  SphColliderPose pose = sphColliderPose(c, t);
  vec3 n;
  float d = sphColliderDistance(c, pose, x, n);
  if (d >= margin) return;
  x += n * (margin - d);
  float vn = dot(v - sphColliderVelocityAt(c, pose, x), n);
  if (vn < 0.0) v -= vn * n;
}
