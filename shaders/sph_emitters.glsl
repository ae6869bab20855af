// The emitters' table (sim_emit.comp, sim_emit_commit.comp). C++: EmitterGpu (gpu_types.h).
struct Emitter {
  dvec2 time;     // start (s), layer period tau = spacing / speed (s)
  vec4 dirSpeed;  // xyz: unit direction, w: speed (m/s)
  uvec4 info;     // x: points per layer, y: first point, z: layers in all, w: 1 for a volume source
  vec4 regionA;   // volume source: box min, or sphere centre with w = radius
  vec4 regionB;   // volume source: box max; w: 1 box, 2 sphere (0: a disc)
};
layout(std430, binding = SPHFX_SSBO_SIM_EMITTERS) readonly buffer SimEmitters { Emitter emitters[]; };

// Layers of emitter e due by the end of the substep (stateTime): the k with start + k tau < t, at most
// all of them.
uint emitterLayersDue(uint e) {
  double x = (stateTime - emitters[e].time.x) / emitters[e].time.y;
  if (!(x > 0.0lf)) return 0u;
  return uint(min(ceil(x), double(emitters[e].info.z)));
}
