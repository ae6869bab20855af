// Emitters, after the integration of every substep (HAS_EMITTERS): one invocation per lattice point of
// every emitter's layer. Layer k of emitter e leaves its disc at start + k tau (tau = spacing / speed)
// and is due once that time is before the substep's end; each due layer not yet emitted is appended
// after the live particles, emitter by emitter, layer by layer, point by point (a fixed order: the run is
// deterministic), at the position it has reached by then with the emitter's velocity. The ids continue
// from dynNextId. Idempotent once the frame is reached (no new layer is due), so the CPU dispatches it
// ungated; sim_emit_commit.comp then advances the counts.
#include "sph_params.glsl"
#include "sph_emitters.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SPHFX_SSBO_SIM_EMITTER_POINTS) readonly buffer SimEmitterPoints { vec4 emitterPoints[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_POS) writeonly buffer SimOutPos { vec4 outPos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_VEL) writeonly buffer SimOutVel { vec4 outVel[]; };
uniform uint uPoints;

void main() {
  uint p = sphfxGlobalIndex();
  if (p >= uPoints) return;
  vec4 point = emitterPoints[p];
  uint e = floatBitsToUint(point.w);
  // Slots taken by the earlier emitters' new layers in this substep.
  uint offset = 0u;
  for (uint f = 0u; f < e; ++f) offset += (emitterLayersDue(f) - dynEmitted[f]) * emitters[f].info.x;
  Emitter em = emitters[e];
  uint first = dynEmitted[e], due = emitterLayersDue(e), local = p - em.info.y;
  for (uint k = first; k < due; ++k) {
    uint slot = dynLive + offset + (k - first) * em.info.x + local;
    if (slot >= simParamsCapacity()) return;  // cannot happen: the buffers hold every emitted particle
    float advanced = float(stateTime - (em.time.x + double(k) * em.time.y)) * em.dirSpeed.w;
    outPos[slot] = vec4(point.xyz + advanced * em.dirSpeed.xyz, uintBitsToFloat(dynNextId + (slot - dynLive)));
    outVel[slot] = vec4(em.dirSpeed.w * em.dirSpeed.xyz, 0.0);
  }
}
