/* Binding points of the DFSPH passes (Bender & Koschier 2015/2017), above the simulation stage's 0-15.
 * Preprocessor-only: included by the sim_dfsph_*.comp programs and by sim/src/dfsph_solver.cpp. */
#ifndef SPHFX_SIM_DFSPH_BINDINGS_H
#define SPHFX_SIM_DFSPH_BINDINGS_H

#define SPHFX_SSBO_SIM_DFSPH_PARTICLE 16  /* vec4 per sorted particle: factor, neighbours, stiffness totals */
#define SPHFX_SSBO_SIM_DFSPH_INCREMENT 17 /* float per sorted particle: this iteration's stiffness increment */
#define SPHFX_SSBO_SIM_DFSPH_WARM 18      /* float per particle id: last divergence stiffness (warm start) */
#define SPHFX_SSBO_SIM_DFSPH_PARTIAL 19   /* float per work group: residual sums of one iteration */
#define SPHFX_SSBO_SIM_DFSPH_CONTROL 20   /* DfsphControl: iteration state, statistics, indirect arguments */
#define SPHFX_SSBO_SIM_DFSPH_NEIGHBORS 21 /* vec4 per (slot, sorted particle): m grad W_ij, j bits */
#define SPHFX_SSBO_SIM_DFSPH_BOUNDARY 22  /* vec4 per sorted particle: sum psi grad W, sum psi v_b . grad W */
#define SPHFX_SSBO_SIM_DFSPH_COUNT 23     /* uint per sorted particle: fluid neighbours in the list */

#endif
