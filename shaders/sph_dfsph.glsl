// DFSPH (Bender & Koschier 2015/2017) data shared by the sim_dfsph_*.comp passes. Needs sph_params.glsl.
//
// Stiffness values are stored dt-free as kappa_i / rho_i: the density solver's total is p / rho^2 (the
// pressure acceleration is -m sum (P_i + P_j) grad W), the divergence solver's total changes velocities
// by -m sum (K_i + K_j) grad W. Both are independent of the time step, so they warm-start the next step.
#include "sph_dfsph_bindings.glsl"

// x: alpha_i / rho_i = 1 / (|sum m grad W|^2 + sum |m grad W|^2), y: neighbours (fluid and boundary),
// z: density stiffness total P of this step, w: divergence stiffness total K of this step.
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_PARTICLE) buffer DfsphParticle { vec4 dfsph[]; };

// Iteration control of the running solve and per-frame statistics ([0] density, [1] divergence).
// C++ mirror: sphfx::sim::DfsphControl.
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_CONTROL) buffer DfsphControl {
  uint dfIteration;  // corrections applied so far in the running solve
  uint dfOpen;       // 1 while the running solve iterates
  uint dfSolves[2];
  uint dfIterSum[2];
  uint dfIterMax[2];
  float dfErrorSum[2];  // final average error of each solve, summed
  float dfErrorMax[2];
  float dfLastError;
  uint dfPad;
  // Indirect dispatch arguments: source, reduce, apply; then their live values.
  uint dfArgs[18];
};

// Kernel gradient of every DFSPH sum (density change, factor, pressure corrections): the spiky gradient
// of the WCSPH force (strong repulsion at short range). The poly6 gradient, consistent with the measured
// density, was tried for D rho/Dt: its flat centre lets particles settle onto wall samples, and the tank
// compressed more.
#define dfsphGrad(d) sphSpikyGrad(d, length(d))

// Neighbour lists, built once per substep by sim_dfsph_factor.comp and read by every solver iteration,
// so that an iteration visits the ~30 neighbours of a particle instead of the ~200 candidates of its
// 27 cells, and evaluates no kernel. Slot k of sorted particle i is entry k * N + i (adjacent
// invocations read adjacent entries). DFSPH_MAX_NEIGHBORS slots per particle (sized from the scene's
// packing, DFSPHSolver::listSlots); a particle with more fluid neighbours stops the run with a clear
// error (SIM_FAIL_NEIGHBORS) rather than losing neighbours.
//   dfNbr[k * N + i]: xyz = m grad W(x_i - x_j), w = j (uint bits)
//   dfCount[i]: fluid neighbours of i in the list
//   dfBoundary[i]: xyz = sum_b psi_b grad W(x_i - x_b), w = sum_b psi_b v_b . grad W(x_i - x_b)
//     (boundary samples do not move during a substep, so their sums are constant in the solves)
#if defined(DFSPH_LIST_READ)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_NEIGHBORS) readonly buffer DfsphNeighbors { vec4 dfNbr[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_COUNT) readonly buffer DfsphCount { uint dfCount[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_BOUNDARY) readonly buffer DfsphBoundary { vec4 dfBoundary[]; };
#elif defined(DFSPH_LIST_WRITE)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_NEIGHBORS) writeonly buffer DfsphNeighbors { vec4 dfNbr[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_COUNT) writeonly buffer DfsphCount { uint dfCount[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_BOUNDARY) writeonly buffer DfsphBoundary { vec4 dfBoundary[]; };
#endif
