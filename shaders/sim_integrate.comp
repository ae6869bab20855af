// Symplectic (semi-implicit) Euler: v += dt a, then x += dt v. Then the last-resort guarantees: clamp
// into the domain (wrap along periodic axes) and project out of colliders (the boundary samples do the
// physical work; this only ensures that no particle tunnels or escapes). Writes the unsorted state the
// next step sorts.
#include "sph_params.glsl"
#if defined(HAS_COLLIDERS)
#include "sph_colliders.glsl"
#endif
#if defined(SIM_COLLIDER_CONTACT) && !defined(SOLVER_DFSPH)
#define SIM_INTEGRATE_COLLIDER_CONTACT  // WCSPH's; DFSPH applies it in its density iterations
#endif
#if defined(SIM_PERIODIC_X) || defined(SIM_PERIODIC_Y) || defined(SIM_PERIODIC_Z) || \
    defined(SIM_INTEGRATE_COLLIDER_CONTACT)
#include "sph_kernels.glsl"
#endif
#if defined(HAS_VOLUME_SOURCES)
#include "sph_emitters.glsl"
// Inside an active volume source (box or sphere emitter) the fluid moves at the source's velocity, as a
// TD's "source velocity": the volume stays an ordered block the emit pass refills, instead of a region
// where new particles are placed among ones that pressure has pushed about.
vec3 sphSourceVelocity(vec3 x, vec3 v) {
  for (uint e = 0u; e < emitters.length(); ++e) {
    Emitter em = emitters[e];
    if (em.info.w != 1u || stateTime < em.time.x ||
        stateTime >= em.time.x + double(em.info.z) * em.time.y)
      continue;
    bool inside = em.regionB.w == 1.0 ? all(greaterThanEqual(x, em.regionA.xyz)) && all(lessThan(x, em.regionB.xyz))
                                      : distance(x, em.regionA.xyz) < em.regionA.w;
    if (inside) return em.dirSpeed.w * em.dirSpeed.xyz;
  }
  return v;
}
#endif
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_VEL) readonly buffer SimVel { vec4 vel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_ACCEL) readonly buffer SimAccel { vec4 accel[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_POS) writeonly buffer SimOutPos { vec4 outPos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_VEL) writeonly buffer SimOutVel { vec4 outVel[]; };
#if defined(SIM_KILL_BOXES)
// SIM_KILL_BOXES boxes, min then max: a particle ending the step inside one is removed.
layout(std430, binding = SPHFX_SSBO_SIM_KILL_BOXES) readonly buffer SimKillBoxes { vec4 killBoxes[]; };
#endif
#if defined(SIM_OPEN_FACES)
// Bit 2 a + side is set for the open face of axis a on side 0 (min) or 1 (max).
bool openFace(int axis, int side) { return (SIM_OPEN_FACES & (1 << (2 * axis + side))) != 0; }
#endif

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= simCounts.x) return;
  float dt = stateDt;
  vec3 v = vel[i].xyz + dt * accel[i].xyz;
#if defined(HAS_VOLUME_SOURCES)
  v = sphSourceVelocity(pos[i].xyz, v);
#endif
#if defined(SIM_INTEGRATE_COLLIDER_CONTACT)
  // fluid.wall_contact at colliders (sphColliderContact()): with this step's dt, against the colliders'
  // pose at its start, where the particle is.
  float rate;
  vec4 contact = sphColliderContact(pos[i].xyz, float(stateTime - double(dt)), rate);
  v = sphWallContact(v, contact.xyz, contact.w, rate, dt);
#endif
  vec3 x = pos[i].xyz + dt * v;
  vec3 lo = simDomainMin.xyz + simViscosity.z, hi = simDomainMax.xyz - simViscosity.z;
  for (int k = 0; k < 3; ++k) {
#if defined(SIM_PERIODIC_X)
    if (k == 0) continue;  // no wall: wrapped below
#endif
#if defined(SIM_PERIODIC_Y)
    if (k == 1) continue;
#endif
#if defined(SIM_PERIODIC_Z)
    if (k == 2) continue;
#endif
#if defined(SIM_OPEN_FACES)
    // An open face has no clamp: the particle leaves, and is removed below.
    if (x[k] < lo[k] && !openFace(k, 0)) { x[k] = lo[k]; v[k] = max(v[k], 0.0); }
    if (x[k] > hi[k] && !openFace(k, 1)) { x[k] = hi[k]; v[k] = min(v[k], 0.0); }
#else
    if (x[k] < lo[k]) { x[k] = lo[k]; v[k] = max(v[k], 0.0); }
    if (x[k] > hi[k]) { x[k] = hi[k]; v[k] = min(v[k], 0.0); }
#endif
  }
#if defined(SIM_PERIODIC_X) || defined(SIM_PERIODIC_Y) || defined(SIM_PERIODIC_Z)
  x = sphWrapPosition(x);  // into [min, max): the grid, the health check and the caches see one image
#endif
#if defined(HAS_COLLIDERS)
  for (uint c = 0u; c < simCounts.z; ++c) sphProjectOutOfCollider(c, float(stateTime), simViscosity.z, x, v);
  // A collider pushing a particle into a wall: the wall wins (the domain guarantee is absolute).
#if defined(SIM_OPEN_FACES)
  for (int k = 0; k < 3; ++k) {
    if (!openFace(k, 0)) x[k] = max(x[k], lo[k]);
    if (!openFace(k, 1)) x[k] = min(x[k], hi[k]);
  }
#else
  x = clamp(x, lo, hi);
#endif
#endif
#if defined(SIM_OPEN_FACES) || defined(SIM_KILL_BOXES)
  // Removal: the particle keeps its slot (and id) until the next grid build sorts it out of the live
  // range (SIM_REMOVED_POSITION, sph_dynamic.glsl).
  bool removed = false;
#if defined(SIM_OPEN_FACES)
  for (int k = 0; k < 3; ++k)
    removed = removed || (openFace(k, 0) && x[k] < simDomainMin[k]) || (openFace(k, 1) && x[k] > simDomainMax[k]);
#endif
#if defined(SIM_KILL_BOXES)
  for (int b = 0; b < SIM_KILL_BOXES; ++b)
    removed = removed || (all(greaterThanEqual(x, killBoxes[2 * b].xyz)) && all(lessThan(x, killBoxes[2 * b + 1].xyz)));
#endif
  if (removed) x = SIM_REMOVED_POSITION;
#endif
  outPos[i] = vec4(x, pos[i].w);
  outVel[i] = vec4(v, vel[i].w);  // w: solver data carried between steps (DFSPH warm start)
}
