// Moves the collider boundary samples to the start of the substep (keyframed translation) and gives
// them the collider's velocity, so moving colliders push and drag the fluid. Wall samples stay put.
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
  vec3 offset = vec3(0.0), v = vec3(0.0);
  if (b != 0xffffffffu) sphColliderMotion(b, float(stateTime), offset, v);
  outPos[i] = vec4(r.xyz + offset, r.w);
  outVel[i] = vec4(v, 0.0);
}
