// Emitters, after the integration of every substep (HAS_EMITTERS): one invocation per lattice point of
// every emitter's layer (a disc's points, or all of a volume source's). Layer k of emitter e leaves at
// start + k tau (tau = spacing / speed)
// and is due once that time is before the substep's end; each due layer not yet emitted is appended
// after the live particles, emitter by emitter, layer by layer, point by point (a fixed order: the run is
// deterministic), at the position it has reached by then with the emitter's velocity. The ids continue
// from dynNextId. Idempotent once the frame is reached (no new layer is due), so the CPU dispatches it
// ungated; sim_emit_commit.comp then advances the counts.
//
// A point with a fluid particle of this substep's grid (its start positions) closer than half a spacing
// is not emitted (its slot and id are taken, and it is removed at the next grid build like a killed
// particle): a splash or a pool that reaches the nozzle blocks it instead of being overlapped, which
// would press two particles into one place and blow them apart.
#include "sph_params.glsl"
#include "sph_emitters.glsl"
#define SPH_FLUID_START(c) cellStart[c]
#define SPH_BOUNDARY_START(c) 0u
#include "sph_neighbors.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = SPHFX_SSBO_SIM_POS) readonly buffer SimPos { vec4 pos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_CELL_START) readonly buffer SimCellStart { uint cellStart[]; };
layout(std430, binding = SPHFX_SSBO_SIM_EMITTER_POINTS) readonly buffer SimEmitterPoints { vec4 emitterPoints[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_POS) writeonly buffer SimOutPos { vec4 outPos[]; };
layout(std430, binding = SPHFX_SSBO_SIM_UNSORTED_VEL) writeonly buffer SimOutVel { vec4 outVel[]; };
uniform uint uPoints;

bool occupied(vec3 x) {
  float r2 = 0.25 * simDomainMax.w * simDomainMax.w;
  SPH_FOR_EACH_CELL_RANGE(x, row, seam, first, last)
    SPH_FOR_EACH_FLUID(j, first, last) {
      vec3 d = x - pos[j].xyz;
      if (dot(d, d) < r2) return true;
    }
  SPH_END_FOR_EACH_CELL_RANGE
  return false;
}

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
    vec3 x = point.xyz + advanced * em.dirSpeed.xyz;
    // A volume source's layers each cover its whole volume: of several due in one substep only the newest
    // is emitted (the older ones would overlap it); their slots hold removed particles.
    bool superseded = em.info.w == 1u && k + 1u < due;
    if (superseded || occupied(x)) x = SIM_REMOVED_POSITION;
    outPos[slot] = vec4(x, uintBitsToFloat(dynNextId + (slot - dynLive)));
    outVel[slot] = vec4(em.dirSpeed.w * em.dirSpeed.xyz, 0.0);
  }
}
