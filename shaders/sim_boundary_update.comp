// Moves the collider boundary samples to the start of the substep (keyframed rigid motion) and gives
// them the body's velocity there (v + omega x r), so moving colliders push and drag the fluid. Wall
// samples stay put. A collider sample beyond a wall (a collider that reaches through the floor, or rises
// from below it) weighs nothing while it is there: the wall's own samples stand for the solid there, and
// both together would double its density next to the junction. Its weight ramps from 0 to psi while it
// crosses the wall's plane between half a spacing beyond and half a spacing inside, so a sample that a
// moving collider carries across a wall does not appear at once (a sample at rest lies on the lattice's
// half spacings: 0 or psi).
#include "sph_params.glsl"
#include "sph_colliders.glsl"
layout(local_size_x = SIM_WG) in;
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_REST) readonly buffer SimBoundaryRest { vec4 rest[]; };
layout(std430, binding = SPHFX_SSBO_SIM_BOUNDARY_BODY) readonly buffer SimBoundaryBody { uint body[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_POS) writeonly buffer SimOutPos { vec4 outPos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_VEL) writeonly buffer SimOutVel { vec4 outVel[]; };

void main() {
  uint i = sphfxGlobalIndex();
  if (i >= simCounts.y) return;
  vec4 r = rest[i];
  uint b = body[i];
  vec3 x = r.xyz, v = vec3(0.0);
  float psi = r.w;
  if (b != 0xffffffffu) {
    SphColliderPose pose = sphColliderPose(b, float(stateTime));
    x = sphColliderToWorld(b, pose, r.xyz);
    v = sphColliderVelocityAt(b, pose, x);
    vec3 inside = min(x - simDomainMin.xyz, simDomainMax.xyz - x);  // < 0 beyond a wall
#if defined(SIM_PERIODIC_X)
    inside.x = 1e30;
#endif
#if defined(SIM_PERIODIC_Y)
    inside.y = 1e30;
#endif
#if defined(SIM_PERIODIC_Z)
    inside.z = 1e30;
#endif
    psi *= clamp(min(inside.x, min(inside.y, inside.z)) / simDomainMax.w + 0.5, 0.0, 1.0);
  }
  outPos[i] = vec4(x, psi);
  outVel[i] = vec4(v, 0.0);
}
