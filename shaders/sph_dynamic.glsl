// The live particle count of a scene whose count changes (SIM_DYNAMIC_COUNT: emitters, kill boxes or open
// faces). The buffers hold simCounts.x particles (the scene's largest possible count); the first dynLive
// of them are particles. The grid build sets dynLive to the particles it sorted into cells (removed ones
// sort to the out-of-reach cell and drop out); the emit pass appends after dynLive. C++:
// Simulator (simulator.cpp).
layout(std430, binding = SPHFX_SSBO_SIM_DYNAMIC) buffer SimDynamic {
  uint dynLive;       // particles in the buffers' first slots
  uint dynNextId;     // id of the next emitted particle (ids are never reused)
  uint dynEmitted[];  // per emitter: lattice layers emitted so far
};

// Position of a removed particle until the next grid build drops it: far outside any grid, so that
// sim_grid_cells.comp puts it into the out-of-reach cell.
#define SIM_REMOVED_POSITION vec3(1e30)
