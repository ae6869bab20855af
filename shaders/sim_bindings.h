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

/* Grid construction programs (sim_grid_*.comp, sim_scan_*.comp): source/destination use 0-3, the
 * cell counts/starts 7. */
#define SPHFX_SSBO_SIM_GRID_CELL_RANK 8
#define SPHFX_SSBO_SIM_GRID_SORTED 9
#define SPHFX_SSBO_SIM_SCAN_DATA 10
#define SPHFX_SSBO_SIM_SCAN_SUMS 11
#define SPHFX_SSBO_SIM_GRID_NEIGHBORS 12

#endif
