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

// Kernel gradients: the density change D rho/Dt and the pressure corrections both use the spiky gradient
// of the WCSPH force (strong repulsion at short range). The poly6 gradient, consistent with the measured
// density, was tried for D rho/Dt: its flat centre lets particles settle onto wall samples, and the tank
// compressed more. The two names keep the factor's coupling of both sums explicit.
#define dfsphDensityGrad(d) sphSpikyGrad(d, length(d))
#define dfsphForceGrad(d) sphSpikyGrad(d, length(d))
