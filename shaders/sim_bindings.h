/* Binding points of the simulation stage (shader storage 0-30, uniform block SPHFX_UBO_SIM_PARAMS).
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
#define SPHFX_SSBO_SIM_BOUNDARY_PRESSURE 17 /* WCSPH: float p_b / rho_b^2 per sorted boundary sample */
#define SPHFX_SSBO_SIM_BOUNDARY_WALL_SHARE 18 /* WCSPH without colliders: float sum psi W over the samples */
#define SPHFX_SSBO_SIM_COLLIDER_FIELD 28 /* float: the mesh/vdb colliders' signed distances, one after another */

/* DFSPH passes (sim_dfsph_*.comp; 16-18 are free there: no DFSPH program uses the WCSPH buffers) */
#define SPHFX_SSBO_SIM_DFSPH_PARTICLE 16  /* vec4 per sorted particle: factor, neighbours, stiffness totals */
#define SPHFX_SSBO_SIM_DFSPH_INCREMENT 17 /* float per sorted particle: an iteration's stiffness increment */
#define SPHFX_SSBO_SIM_DFSPH_WARM 18      /* float per particle id: last divergence stiffness (warm start) */
#define SPHFX_SSBO_SIM_DFSPH_PARTIAL 19   /* float per work group: residual sums of one iteration */
#define SPHFX_SSBO_SIM_DFSPH_CONTROL 20   /* DfsphControl: iteration state, statistics, indirect arguments */
#define SPHFX_SSBO_SIM_DFSPH_NEIGHBORS 21 /* vec4 per (slot, sorted particle): m grad W_ij, j bits */
#define SPHFX_SSBO_SIM_DFSPH_BOUNDARY 22  /* vec4 per sorted particle: sum psi grad W, sum psi v_b . grad W */
#define SPHFX_SSBO_SIM_DFSPH_COUNT 23     /* uint per sorted particle: fluid neighbours in the list */
#define SPHFX_SSBO_SIM_DFSPH_WET 29       /* constraint walls: dispatch arguments, count, the samples near fluid */
#define SPHFX_SSBO_SIM_DFSPH_PRESSURE_IMPULSE 30 /* float per particle id: the frame's pressure impulse */

/* Varying particle counts (scenes with emitters, kill boxes or open faces; sph_dynamic.glsl) */
#define SPHFX_SSBO_SIM_DYNAMIC 24         /* SimDynamic: live count, next id, layers emitted per emitter */
#define SPHFX_SSBO_SIM_EMITTERS 25        /* per emitter: timing, direction and speed, point range */
#define SPHFX_SSBO_SIM_EMITTER_POINTS 26  /* vec4 per emitter lattice point: xyz, w = emitter index bits */
#define SPHFX_SSBO_SIM_KILL_BOXES 27      /* vec4 min, vec4 max per kill box */

/* Texture units (buffer textures, read-only views of the buffers above, sph_textures.glsl): neighbour
 * loops fetch through these. */
#define SPHFX_TEX_SIM_POS 0 /* RGBA32F view of SPHFX_SSBO_SIM_POS */
#define SPHFX_TEX_SIM_VEL 1 /* RGBA32F, SPHFX_SSBO_SIM_VEL */
#define SPHFX_TEX_SIM_DENSITY 2 /* RG32F, SPHFX_SSBO_SIM_DENSITY */
#define SPHFX_TEX_SIM_CELL_START 3 /* R32UI, SPHFX_SSBO_SIM_CELL_START */
#define SPHFX_TEX_SIM_BOUNDARY_POS 4 /* RGBA32F, SPHFX_SSBO_SIM_BOUNDARY_POS */
#define SPHFX_TEX_SIM_BOUNDARY_VEL 5 /* RGBA32F, SPHFX_SSBO_SIM_BOUNDARY_VEL */
#define SPHFX_TEX_SIM_BOUNDARY_CELL_START 6 /* R32UI, SPHFX_SSBO_SIM_BOUNDARY_CELL_START */
#define SPHFX_TEX_SIM_DFSPH_NEIGHBORS 7 /* RGBA32F, SPHFX_SSBO_SIM_DFSPH_NEIGHBORS */
#define SPHFX_TEX_SIM_DFSPH_INCREMENT 8 /* R32F, SPHFX_SSBO_SIM_DFSPH_INCREMENT */
#define SPHFX_TEX_SIM_DFSPH_PARTICLE 9 /* RGBA32F, the DFSPH per-particle factor, count and totals */
#define SPHFX_TEX_SIM_DFSPH_COUNT 10 /* R32UI, the DFSPH neighbour counts */
#define SPHFX_TEX_SIM_DFSPH_BOUNDARY 11 /* RGBA32F, the DFSPH boundary sums */

/* Grid construction programs (sim_grid_*.comp, sim_scan_*.comp), for the fluid and the boundary samples:
 * the items to sort (source) and their sorted copies (destination), the cell counts/starts at 7. */
#define SPHFX_SSBO_SIM_GRID_SRC_POS 0
#define SPHFX_SSBO_SIM_GRID_SRC_VEL 1
#define SPHFX_SSBO_SIM_GRID_DST_POS 2
#define SPHFX_SSBO_SIM_GRID_DST_VEL 3
#define SPHFX_SSBO_SIM_GRID_CELL_RANK 8
#define SPHFX_SSBO_SIM_GRID_SORTED 9
#define SPHFX_SSBO_SIM_SCAN_DATA 10
#define SPHFX_SSBO_SIM_SCAN_SUMS 11
#define SPHFX_SSBO_SIM_GRID_NEIGHBORS 12
#define SPHFX_SSBO_SIM_GRID_ROW_START 13 /* with SIM_GRID_SPLIT_X: the walks' starts (NeighborGrid) */

#endif
