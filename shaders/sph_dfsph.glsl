// DFSPH (Bender & Koschier 2015/2017) data shared by the sim_dfsph_*.comp passes. Needs sph_params.glsl.
//
// Stiffness values are stored dt-free as kappa_i / rho_i: the density solver's total is p / rho^2 (the
// pressure acceleration is -m sum (P_i + P_j) grad W), the divergence solver's total changes velocities
// by -m sum (K_i + K_j) grad W. Both are independent of the time step, so they warm-start the next step.
#include "sph_textures.glsl"

// The particles the buffers hold: where the wall samples' entries start in the buffers indexed by
// particles and then samples (dfsph, the increments, dfCount, dfBoundary's second half), and the stride of
// the lists' slots. With a varying count (SIM_DYNAMIC_COUNT, sph_params.glsl) simCounts.x is the live
// count while the capacity stays fixed, so a sample's rest share and warm start keep their place as
// particles come and go.
#if defined(SIM_DYNAMIC_COUNT)
#define DFSPH_CAPACITY simParamsCapacity()
#else
#define DFSPH_CAPACITY simCounts.x
#endif

// x: the constant-density solve's factor alpha_i / rho_i, 1 / (g . (g + (c - 1) sum_b psi_b grad W_ib) +
// sum_j |m grad W_ij|^2) with g = sum_j m grad W_ij + sum_b psi_b grad W_ib (its walls push c =
// DFSPH_DENSITY_WALL_PUSH times; psi_b here includes dfsphWallScale()); y: the divergence solve's,
// 1 / (|g|^2 + sum_j |m grad W_ij|^2), or 0 where the particle has too few neighbours for a divergence
// estimate (free surface, splashes);
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
  uint dfUnconverged[2];  // solves that stopped at DFSPH_MAX_ITER above their tolerance
  // Indirect dispatch arguments: source, reduce, apply; then their live values.
  uint dfArgs[18];
  // DFSPH_CLOSED_PERIODIC: the mean density of the substep's start less the rest density, which the
  // constant-density solve's residuals leave out (sim_dfsph_begin.comp).
  float dfMeanExcess;
  uint dfPad[2];  // the GL rounds the block's size up to 16 bytes
};

// DFSPH_CLOSED_PERIODIC (DFSPHSolver::closedPeriodic: fluid fills a domain periodic along every axis,
// with no colliders): the constant-density solve is a Poisson problem with periodic boundaries, solvable
// only for a source of zero mean. Its corrections cannot change the mean predicted density (the pair
// sums cancel), and the kernel sum of a disordered packing differs from the lattice's at the same volume,
// so the mean density of the fixed volume drifts from rest; the solve targets the mean instead. The
// factor pass writes each work group's density sum to partial[DFSPH_RESIDUAL_SLOTS + group], after the
// iterations' residual sums (DFSPHSolver::residualSlots).

// The DFSPH kernel: its gradient is that of every DFSPH sum (density change, factor, pressure
// corrections), and the walls enter the DFSPH density and every gradient sum as psi_b times its W
// weighted by dfsphWallScale().
// Default: the spiky kernel of the WCSPH force, whose strong short-range repulsion keeps particles off
// the wall samples (poly6's flat centre lets them settle onto the samples and the tank compress): a
// particle pressed into a wall sees its density rise steeply (9 % at 0.2 spacings from a flat wall's
// resting site; poly6: 1.1 %). Spiky W = 15 / (pi h^6) (h - r)^3 (simKernel.y is its gradient's -45 /
// (pi h^6)).
// DFSPH_KERNEL_WENDLAND (solver.dfsph.density_kernel "wendland_c2"): Wendland C2, W = DFSPH_WENDLAND_W (1
// - q)^4 (1 + 4 q) and grad W = DFSPH_WENDLAND_GRAD (1 - q)^3 d, q = r / h, for the fluid's density too.
// The cubic lattice sums lowest under it among the cubic, bcc and fcc packings, so a loaded column keeps
// it (bench/lattice_sums.py); under the spiky kernel it gives way to a closer packing.
#if defined(DFSPH_KERNEL_WENDLAND)
float dfsphW(float r) {
  float q = r / simDomainMin.w, t = max(1.0 - q, 0.0);
  return DFSPH_WENDLAND_W * t * t * t * t * (1.0 + 4.0 * q);
}
vec3 dfsphGradAt(vec3 d, float r) {
  float t = max(1.0 - r / simDomainMin.w, 0.0);
  return (DFSPH_WENDLAND_GRAD * t * t * t) * d;
}
#else
float dfsphW(float r) {
  float q = max(simDomainMin.w - r, 0.0);
  return (-simKernel.y / 3.0) * q * q * q;
}
#define dfsphGradAt(d, r) sphSpikyGrad(d, r)  // (sph_kernels.glsl, in the passes that take gradients)
#endif
#define dfsphGrad(d) dfsphGradAt(d, length(d))

// The weights (DFSPHSolver::spikyWallScales) make the resting lattice sum to the poly6 rest density
// next to faces, edges and corners: a sample beyond one, two or three of the domain's walls (collider
// samples, inside the domain, count as a face). (Defined for the passes that sum over samples:
// DFSPHSolver::factorDefines.)
// solver.dfsph.density_kernel "spiky" or "wendland_c2" (DFSPH_KERNEL_DENSITY, DFSPHSolver::
// densityMassScale): the fluid's density is the DFSPH kernel's sum too, every DFSPH sum takes the particle
// mass times the scale and every class of sample weighs the scale, so that a solve's predicted density
// change is the change of the sum it corrects. The viscosity keeps the plain mass.
// The stiffness totals are p / rho^2 per unit of the mass the sums take: with the kernel density's
// scaled mass the pressure acceleration -m' sum (P_i + P_j) grad W is SPH's -m sum (p_i / rho_i^2 + ...)
// for p / rho^2 = (m' / m) P, so the pressure written for the cache is DFSPH_PRESSURE_SCALE (m' / m) P.
#ifndef DFSPH_PRESSURE_SCALE
#define DFSPH_PRESSURE_SCALE 1.0
#endif

#if defined(DFSPH_WALL_SPIKY_FACE)
float dfsphWallScale(vec3 xb) {
  vec3 above = step(simDomainMax.xyz, xb), below = step(xb, simDomainMin.xyz);
#if defined(SIM_OPEN_FACES)
  // An open face has no wall: the walls beside it continue past it (their samples there are theirs).
  // Bit 2 a + side: the face of axis a on side 0 (min) or 1 (max).
  below *= vec3((SIM_OPEN_FACES & 1) == 0, (SIM_OPEN_FACES & 4) == 0, (SIM_OPEN_FACES & 16) == 0);
  above *= vec3((SIM_OPEN_FACES & 2) == 0, (SIM_OPEN_FACES & 8) == 0, (SIM_OPEN_FACES & 32) == 0);
#endif
  vec3 beyond = above + below;
  float walls = beyond.x + beyond.y + beyond.z;
  return walls > 2.5 ? DFSPH_WALL_SPIKY_CORNER : (walls > 1.5 ? DFSPH_WALL_SPIKY_EDGE : DFSPH_WALL_SPIKY_FACE);
}
#endif

// The constant-density solve's walls push with DFSPH_DENSITY_WALL_PUSH P_i psi_b grad W
// (solver.dfsph.density_wall_push, 1.5 by default: the particle's stiffness plus half of it mirrored onto
// the sample, which holds a resting bottom layer up against the fluid above it), plus the hydrostatic rise
// g . (x_b - x_i) / rho_i (after Adami et al. 2012, as the WCSPH force). 1 x (Akinci 2012) lets the layer
// sink (hydrostatic L2 0.61); 2 x diverges from rest. The divergence solve's walls push 1 x.
// Constraint walls (solver.dfsph.walls, DFSPH_BOUNDARY_CONSTRAINTS; sim_dfsph_boundary_factor.comp):
// the push is 1 x plus each sample's own stiffness k_b, -sum_b k_b psi_b grad W_ib, and no hydrostatic rise.
#ifndef DFSPH_DENSITY_WALL_PUSH
#error "DFSPH_DENSITY_WALL_PUSH: set by DFSPHSolver from solver.dfsph.density_wall_push"
#endif

// The constant-density solve's warm share in this substep: DFSPH_DENSITY_WARM_SHARE
// (solver.dfsph.density_warm_share), with DFSPH_WARM_FLOW_LIMITED only after a substep whose step the flow
// set (density_warm_steps "flow_limited"; sim_timestep.comp). The passes before the substep's
// sim_timestep.comp read that from stateFlowLimited, the passes after it from stateWarmDensity.
#if defined(DFSPH_WARM_FLOW_LIMITED)
#define DFSPH_DENSITY_WARM_BEFORE_STEP (stateFlowLimited != 0u ? DFSPH_DENSITY_WARM_SHARE : 0.0)
#define DFSPH_DENSITY_WARM_AFTER_STEP (stateWarmDensity != 0u ? DFSPH_DENSITY_WARM_SHARE : 0.0)
#else
#define DFSPH_DENSITY_WARM_BEFORE_STEP DFSPH_DENSITY_WARM_SHARE
#define DFSPH_DENSITY_WARM_AFTER_STEP DFSPH_DENSITY_WARM_SHARE
#endif

// Neighbour lists, built once per substep by sim_dfsph_factor.comp and read by every solver iteration,
// so that an iteration visits the ~30 neighbours of a particle instead of the ~200 candidates of its
// 27 cells, and evaluates no kernel. The writer (sim_dfsph_factor.comp) uses the storage blocks below,
// the readers the buffer-texture views (dfsphEntry() etc.). Slot k of sorted particle i is entry k * N + i,
// N = DFSPH_CAPACITY here and below (adjacent invocations read adjacent entries). DFSPH_MAX_NEIGHBORS
// slots per particle (sized from the scene's packing, DFSPHSolver::listSlots) and one spare (the factor
// pass writes every candidate to the slot after the last neighbour); a particle with more fluid
// neighbours stops the run with a clear error (SIM_FAIL_NEIGHBORS) rather than losing neighbours.
//   dfNbr[k * N + i]: xyz = m grad W(x_i - x_j), w = j (uint bits)
//   dfCount[i]: fluid neighbours of i in the list (low 16 bits; constraint walls: wall entries above)
//   dfBoundary[i]: xyz = sum_b psi_b grad W(x_i - x_b), w = sum_b psi_b v_b . grad W(x_i - x_b)
//     (boundary samples do not move during a substep, so their sums are constant in the solves);
//     with DFSPH_WALL_LAPLACIAN_SUM instead w = sum_b psi_b lap W(x_i - x_b) (see below)
//   dfBoundary[N + i] (fluid.wall_contact, SIM_WALL_CONTACT): x = the walls' kernel sum over i less
//     SIM_WALL_CONTACT_REST where i has fewer than SIM_WALL_CONTACT neighbours, else -1e30 (the contact,
//     sphWallContact() in sph_kernels.glsl, never acts); y (SIM_COLLIDER_CONTACT) the nearest collider
//     surface's velocity along its constraint's gradient
//   dfBoundary[2N + i] (SIM_COLLIDER_CONTACT): the nearest collider's contact constraint on i, whatever
//     its neighbours (sphColliderContact() in sph_colliders.glsl)
// Walls at rest (no colliders) and Laplacian viscosity: the walls' viscous term is
// nu / rho_i sum_b psi_b lap W_ib (0 - v_i) = -(nu / rho_i) v_i sum_b psi_b lap W_ib, so the factor pass
// sums psi_b lap W_ib in its boundary loop (in dfBoundary.w, where the walls' velocity term is 0) and the
// non-pressure pass needs no boundary walk of its own.
#if defined(VISCOSITY_LAPLACIAN) && defined(SIM_WALL_VISCOSITY) && !defined(HAS_COLLIDERS)
#define DFSPH_WALL_LAPLACIAN_SUM
#endif

#if defined(DFSPH_LIST_READ)
// The list entries and the increments are read per neighbour, through texel fetches (sph_textures.glsl).
layout(binding = SPHFX_TEX_SIM_DFSPH_NEIGHBORS) uniform samplerBuffer dfNbrTex;
layout(binding = SPHFX_TEX_SIM_DFSPH_INCREMENT) uniform samplerBuffer dfIncrementTex;
layout(binding = SPHFX_TEX_SIM_DFSPH_PARTICLE) uniform samplerBuffer dfParticleTex;
layout(binding = SPHFX_TEX_SIM_DFSPH_COUNT) uniform usamplerBuffer dfCountTex;
layout(binding = SPHFX_TEX_SIM_DFSPH_BOUNDARY) uniform samplerBuffer dfBoundaryTex;
vec4 dfsphEntry(uint i, uint k) { return texelFetch(dfNbrTex, int(k * DFSPH_CAPACITY + i)); }
float dfsphIncrement(uint j) { return texelFetch(dfIncrementTex, int(j)).x; }
// Per-particle values read through the views too (one gather instead of a load per lane on llvmpipe;
// a pass may read its own particle's value this way before writing it through the storage block).
vec4 dfsphParticle(uint i) { return texelFetch(dfParticleTex, int(i)); }
uint dfsphCount(uint i) { return texelFetch(dfCountTex, int(i)).x & 0xffffu; }
#if defined(DFSPH_BOUNDARY_CONSTRAINTS)
// Wall entries (constraint walls): slot DFSPH_MAX_NEIGHBORS - 1 - k for k < dfsphBoundaryCount(i),
// xyz = psi_b grad W(x_i - x_b), w = the sorted sample index b; the sample's stiffness (dfsph[N + b],
// increment N + b) follows the particles'. dfCount's high 16 bits hold the wall entries' count.
uint dfsphBoundaryCount(uint i) { return texelFetch(dfCountTex, int(i)).x >> 16u; }
vec4 dfsphBoundaryEntry(uint i, uint k) {
  return texelFetch(dfNbrTex, int((uint(DFSPH_MAX_NEIGHBORS) - 1u - k) * DFSPH_CAPACITY + i));
}
#endif
vec4 dfsphBoundary(uint i) { return texelFetch(dfBoundaryTex, int(i)); }
#if defined(SIM_WALL_CONTACT)
float dfsphWallContactExcess(uint i) { return texelFetch(dfBoundaryTex, int(DFSPH_CAPACITY + i)).x; }
#if defined(SIM_COLLIDER_CONTACT)
float dfsphColliderContactRate(uint i) { return texelFetch(dfBoundaryTex, int(DFSPH_CAPACITY + i)).y; }
vec4 dfsphColliderContact(uint i) { return texelFetch(dfBoundaryTex, int(2u * DFSPH_CAPACITY + i)); }
#endif
#endif
#endif
#if defined(DFSPH_LIST_WRITE)
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_NEIGHBORS) writeonly buffer DfsphNeighbors { vec4 dfNbr[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_COUNT) writeonly buffer DfsphCount { uint dfCount[]; };
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_BOUNDARY) writeonly buffer DfsphBoundary { vec4 dfBoundary[]; };
#endif

#if defined(DFSPH_BOUNDARY_CONSTRAINTS) && !defined(SIM_VISIT_EVERY_SAMPLE)
// Samples that fluid may reach, marked: the particles' factor pass sets dfCount[N + b] to 1 for every
// sample its walk visits, a superset of those within h of a particle, and the samples' factor pass
// (sim_dfsph_boundary_factor.comp) skips a sample whose count is 0: not marked, and its slot's sample had
// no fluid within h at its last pass (a non-zero Jacobi diagonal, dfsph[N + b].x, needs one). Such a
// sample sums nothing and would write what the slot holds already: without colliders what it wrote when
// fluid last left it, with colliders (which re-sort the samples every substep) the zeros of every sample
// without fluid near; a slot never written differs only in dfsph[N + b].y, which is read for samples near
// fluid alone. So a domain far larger than its fluid costs little more than its wet walls, with the same
// caches bit for bit (SIM_VISIT_EVERY_SAMPLE, sim::visitEverySample(), visits them all).
#define DFSPH_SAMPLES_MARKED
#endif

#if defined(DFSPH_BOUNDARY_CONSTRAINTS) && (defined(DFSPH_LIST_READ) || defined(DFSPH_LIST_WRITE))
// Each wall sample's list of fluid neighbours (constraint walls), the transpose of the particles' wall
// entries, built by sim_dfsph_boundary_factor.comp and read by every iteration of the constant-density
// solve (sim_dfsph_boundary_source.comp), so that an iteration visits a sample's listed neighbours
// instead of walking its 27 cells. After the particles' lists: slot k of sorted sample b is entry
// dfsphSampleSlot(b, k) (adjacent samples read adjacent entries), DFSPH_MAX_NEIGHBORS slots and one spare
// as the particles'; its count is dfCount[N + b].
//   xyz = psi_b grad W(x_f - x_b) (the particle's wall entry for b), w = f (uint bits)
uint dfsphSampleSlot(uint b, uint k) {
  return DFSPH_CAPACITY * uint(DFSPH_MAX_NEIGHBORS + 1) + k * simCounts.y + b;
}
#if defined(DFSPH_LIST_READ)
vec4 dfsphSampleEntry(uint b, uint k) { return texelFetch(dfNbrTex, int(dfsphSampleSlot(b, k))); }
uint dfsphSampleCount(uint b) { return texelFetch(dfCountTex, int(DFSPH_CAPACITY + b)).x; }
#endif
#endif

#if defined(DFSPH_WET_LIST)
// The wall samples with fluid near them this substep (a non-zero Jacobi diagonal), appended by
// sim_dfsph_boundary_factor.comp in whatever order its invocations reach them; the constant-density
// iterations' sample passes (sim_dfsph_boundary_source.comp) run over these alone, dispatched through
// dfWetArgs. A sample's update reads only its own data, so the order changes no result. C++ resets the
// header before the factor pass (DFSPHSolver::computeDensity).
layout(std430, binding = SPHFX_SSBO_SIM_DFSPH_WET) buffer DfsphWet {
  uint dfWetArgs[3];  // indirect dispatch: work groups over the list, 1, 1
  uint dfWetCount;
  uint dfWet[];  // sorted sample indices
};
#endif
