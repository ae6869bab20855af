// Opens a DFSPH solve (one invocation): its indirect dispatches run only while the time step pass keeps
// the substep alive (gate word DFSPH_GATE_WORD non-zero). The divergence solve, the first of a substep,
// also resets the frame statistics at the frame's first substep. DFSPH_CLOSED_PERIODIC: the
// constant-density solve's begin sums the factor pass's group densities into dfMeanExcess.
#include "sph_params.glsl"
#include "sph_dfsph.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = SPHFX_SSBO_SIM_DISPATCH) readonly buffer SimDispatch { uint dispatchArgs[]; };
#if defined(DFSPH_CLOSED_PERIODIC) && !defined(DFSPH_DIVERGENCE)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_PARTIAL) readonly buffer DfsphPartial { float partial[]; };
#endif

void main() {
#if defined(DFSPH_DIVERGENCE)
  if (stateSubsteps == 0u && stateDone == 0u)
    for (uint s = 0u; s < 2u; ++s) {
      dfSolves[s] = 0u;
      dfIterSum[s] = 0u;
      dfIterMax[s] = 0u;
      dfErrorSum[s] = 0.0;
      dfErrorMax[s] = 0.0;
      dfUnconverged[s] = 0u;
    }
#endif
#if defined(DFSPH_CLOSED_PERIODIC) && !defined(DFSPH_DIVERGENCE)
  float sum = 0.0;
  for (uint k = 0u; k < uint(DFSPH_GROUPS); ++k) sum += partial[uint(DFSPH_RESIDUAL_SLOTS) + k];
  dfMeanExcess = sum / float(simCounts.x) - simFluid.x;
#endif
  bool open = dispatchArgs[uint(DFSPH_GATE_WORD)] != 0u;
  dfIteration = 0u;
  dfOpen = open ? 1u : 0u;
  for (uint k = 0u; k < 9u; ++k) dfArgs[k] = open ? dfArgs[9u + k] : 0u;
}
