// Colliders: shapes at rest plus keyframed translation. C++ mirror: sphfx::sim::ColliderGpu.
struct SimCollider {
  vec4 shapeA;  // box: min corner; sphere: centre, w = radius
  vec4 shapeB;  // box: max corner
  uvec4 info;   // x: 0 box / 1 sphere, y: first key, z: key count
};
layout(std430, binding = SPHFX_SSBO_SIM_COLLIDERS) readonly buffer SimColliders { SimCollider colliders[]; };
// x: key time, yzw: offset from the rest placement
layout(std430, binding = SPHFX_SSBO_SIM_COLLIDER_KEYS) readonly buffer SimColliderKeys { vec4 colliderKeys[]; };

// Translation and velocity of collider c at time t: linear between keys, held outside them.
void sphColliderMotion(uint c, float t, out vec3 offset, out vec3 velocity) {
  uint first = colliders[c].info.y, n = colliders[c].info.z;
  offset = vec3(0.0);
  velocity = vec3(0.0);
  if (n == 0u) return;
  vec4 k0 = colliderKeys[first];
  offset = k0.yzw;
  if (t <= k0.x) return;
  for (uint k = 1u; k < n; ++k) {
    vec4 k1 = colliderKeys[first + k];
    if (t < k1.x) {
      float s = (t - k0.x) / (k1.x - k0.x);
      offset = mix(k0.yzw, k1.yzw, s);
      velocity = (k1.yzw - k0.yzw) / (k1.x - k0.x);
      return;
    }
    k0 = k1;
    offset = k0.yzw;
  }
}

// Pushes a particle at x out of collider c (placed for time t) to `margin` outside its surface, and
// removes the velocity component into the collider relative to the collider's own velocity.
void sphProjectOutOfCollider(uint c, float t, float margin, inout vec3 x, inout vec3 v) {
  vec3 offset, cv;
  sphColliderMotion(c, t, offset, cv);
  vec3 n = vec3(0.0);
  if (colliders[c].info.x == 0u) {
    vec3 lo = colliders[c].shapeA.xyz + offset - margin, hi = colliders[c].shapeB.xyz + offset + margin;
    if (any(lessThanEqual(x, lo)) || any(greaterThanEqual(x, hi))) return;
    vec3 toLo = x - lo, toHi = hi - x;  // both positive inside: leave through the nearest face
    float best = toLo.x;
    n = vec3(-1, 0, 0);
    for (int k = 0; k < 3; ++k) {
      if (toLo[k] < best) { best = toLo[k]; n = vec3(0.0); n[k] = -1.0; }
      if (toHi[k] < best) { best = toHi[k]; n = vec3(0.0); n[k] = 1.0; }
    }
    x += n * best;
  } else {
    vec3 d = x - (colliders[c].shapeA.xyz + offset);
    float r = colliders[c].shapeA.w + margin, len = length(d);
    if (len >= r) return;
    n = len > 1e-12 ? d / len : vec3(0, 1, 0);
    x += n * (r - len);
  }
  float vn = dot(v - cv, n);
  if (vn < 0.0) v -= vn * n;
}
