// Moves the collider boundary samples to the start of the substep (keyframed rigid motion) and gives
// them the body's velocity there (v + omega x r), so moving colliders push and drag the fluid. Wall
// samples stay put.
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
  if (b != 0xffffffffu) {
    SphColliderPose pose = sphColliderPose(b, float(stateTime));
    x = sphColliderToWorld(b, pose, r.xyz);
    v = sphColliderVelocityAt(b, pose, x);
  }
  outPos[i] = vec4(x, r.w);
  outVel[i] = vec4(v, 0.0);
}
