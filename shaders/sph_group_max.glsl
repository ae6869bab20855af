// The largest values of a pass, into the state block's stateMax* words (sph_params.glsl): non-negative
// floats as uint bits, which order as the floats (NaN's bits are larger than any), e.g. the fastest
// particle for the CFL step. In uniform control flow:
//   SIM_GROUP_MAX_BEGIN(); ... SIM_GROUP_MAX(k, stateMaxSpeed2, bits) for live items ...;
//   SIM_GROUP_MAX_END(); SIM_GROUP_MAX_FLUSH(k, stateMaxSpeed2) for each word k < 2.
// SIM_WORKGROUP_REDUCE (hardware GPUs; sphfx::sim::workgroupReduce()): a work group's values meet in
// shared memory behind two barriers, then one global atomic per group. Otherwise (CPU rasterisers such
// as llvmpipe, where barriers cost more than the atomics; docs/performance.md, "Simulation"): one
// global atomic per invocation, no barrier. A maximum does not depend on the order: both give the
// same bits.
#if defined(SIM_WORKGROUP_REDUCE)
shared uint simGroupMax[2];
#define SIM_GROUP_MAX_BEGIN()                                                    \
  if (gl_LocalInvocationIndex < 2u) simGroupMax[gl_LocalInvocationIndex] = 0u; \
  barrier()
#define SIM_GROUP_MAX(k, word, bits) atomicMax(simGroupMax[k], bits)
#define SIM_GROUP_MAX_END() barrier()
#define SIM_GROUP_MAX_FLUSH(k, word) \
  if (gl_LocalInvocationIndex == 0u) atomicMax(word, simGroupMax[k])
#else
#define SIM_GROUP_MAX_BEGIN()
#define SIM_GROUP_MAX(k, word, bits) atomicMax(word, bits)
#define SIM_GROUP_MAX_END()
#define SIM_GROUP_MAX_FLUSH(k, word)
#endif
