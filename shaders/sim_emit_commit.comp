// After sim_emit.comp, one invocation: the emitted layers join the live particles (count, next id, the
// emitters' layer counts). With uSync (a restored state), it only sets the layer counts and the next id
// from the time, as a run that reached this time would have them: the state between frames is then just
// the particles (restart files need nothing else).
#include "sph_params.glsl"
#include "sph_emitters.glsl"
layout(local_size_x = 1) in;
uniform uint uEmitters;
uniform uint uSync;
uniform uint uInitialParticles;

void main() {
  uint added = 0u, emitted = 0u;
  for (uint e = 0u; e < uEmitters; ++e) {
    uint due = emitterLayersDue(e);
    added += (due - dynEmitted[e]) * emitters[e].info.x;
    emitted += due * emitters[e].info.x;
    dynEmitted[e] = due;
  }
  if (uSync != 0u) {
    dynNextId = uInitialParticles + emitted;
  } else {
    dynLive += added;
    dynNextId += added;
  }
}
