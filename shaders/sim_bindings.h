/* Binding points of the simulation stage (shader storage 0-15, uniform block SPHFX_UBO_SIM_PARAMS).
 * Preprocessor-only; included by bindings.h. C++ mirrors: sim/include/sphfx/sim/gpu_types.h. */
#ifndef SPHFX_SIM_BINDINGS_H
#define SPHFX_SIM_BINDINGS_H

/* Solver passes (sim_density, sim_force, sim_integrate, sim_timestep, sim_health, sim_boundary_update) */
#define SPHFX_SSBO_SIM_UNSORTED_POS 0 /* vec4 xyz, w = id bits: the state between steps */
#define SPHFX_SSBO_SIM_UNSORTED_VEL 1
#define SPHFX_SSBO_SIM_POS 2 /* the same, sorted by cell */
#define SPHFX_SSBO_SIM_VEL 3
#define SPHFX_SSBO_SIM_DENSITY 4 /* vec2: density, pressure / density^2 */
#define SPHFX_SSBO_SIM_ACCEL 5
#define SPHFX_SSBO_SIM_STATE 6 /* SimState: time, dt, reductions, health counters */
#define SPHFX_SSBO_SIM_CELL_START 7
#define SPHFX_SSBO_SIM_BOUNDARY_POS 8 /* vec4 xyz, w = Akinci volume psi, sorted by cell */
#define SPHFX_SSBO_SIM_BOUNDARY_VEL 9
#define SPHFX_SSBO_SIM_BOUNDARY_CELL_START 10
#define SPHFX_SSBO_SIM_COLLIDERS 11
#define SPHFX_SSBO_SIM_COLLIDER_KEYS 12
#define SPHFX_SSBO_SIM_BOUNDARY_REST 13
#define SPHFX_SSBO_SIM_BOUNDARY_BODY 14
#define SPHFX_SSBO_SIM_DISPATCH 15 /* indirect dispatch arguments, then their live values */
#define SPHFX_SSBO_SIM_NEIGHBORS 16 /* WCSPH: neighbours found by sim_density, used by sim_force */

/* Texture units (buffer textures, read-only views of the buffers above, sph_textures.glsl): neighbour
 * loops fetch through these. */
#define SPHFX_TEX_SIM_POS 0 /* RGBA32F view of SPHFX_SSBO_SIM_POS */
#define SPHFX_TEX_SIM_VEL 1 /* RGBA32F, SPHFX_SSBO_SIM_VEL */
#define SPHFX_TEX_SIM_DENSITY 2 /* RG32F, SPHFX_SSBO_SIM_DENSITY */
#define SPHFX_TEX_SIM_CELL_START 3 /* R32UI, SPHFX_SSBO_SIM_CELL_START */
#define SPHFX_TEX_SIM_BOUNDARY_POS 4 /* RGBA32F, SPHFX_SSBO_SIM_BOUNDARY_POS */
#define SPHFX_TEX_SIM_BOUNDARY_VEL 5 /* RGBA32F, SPHFX_SSBO_SIM_BOUNDARY_VEL */
#define SPHFX_TEX_SIM_BOUNDARY_CELL_START 6 /* R32UI, SPHFX_SSBO_SIM_BOUNDARY_CELL_START */
#define SPHFX_TEX_SIM_DFSPH_NEIGHBORS 7 /* RGBA32F, the DFSPH neighbour lists (sph_dfsph_bindings.glsl) */
#define SPHFX_TEX_SIM_DFSPH_INCREMENT 8 /* R32F, the DFSPH stiffness increments */
#define SPHFX_TEX_SIM_DFSPH_PARTICLE 9 /* RGBA32F, the DFSPH per-particle factor, count and totals */
#define SPHFX_TEX_SIM_DFSPH_COUNT 10 /* R32UI, the DFSPH neighbour counts */
#define SPHFX_TEX_SIM_DFSPH_BOUNDARY 11 /* RGBA32F, the DFSPH boundary sums */

/* Grid construction programs (sim_grid_*.comp, sim_scan_*.comp): source/destination use 0-3, the
 * cell counts/starts 7. */
#define SPHFX_SSBO_SIM_GRID_CELL_RANK 8
#define SPHFX_SSBO_SIM_GRID_SORTED 9
#define SPHFX_SSBO_SIM_SCAN_DATA 10
#define SPHFX_SSBO_SIM_SCAN_SUMS 11
#define SPHFX_SSBO_SIM_GRID_NEIGHBORS 12
#define SPHFX_SSBO_SIM_GRID_ROW_START 13 /* with SIM_GRID_SPLIT_X: the walks' starts (NeighborGrid) */

#endif
