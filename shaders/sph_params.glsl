// Work group size of the per-particle passes (C++: sphfx::sim::kSimWorkGroup sets it).
#ifndef SIM_WG
#define SIM_WG 64
#endif

// Scene constants of the simulation. C++ mirror: sphfx::sim::SimParams (sim/include/sphfx/sim/gpu_types.h).
layout(std140, binding = SPHFX_UBO_SIM_PARAMS) uniform SimParams {
  vec4 simDomainMin;   // xyz; w: kernel support radius h
  vec4 simDomainMax;   // xyz; w: particle spacing
  vec4 simGravity;     // xyz; w: particle mass
  ivec4 simGridDims;   // xyz: cells; w: number of cells (= index of the out-of-grid cell)
  vec4 simKernel;      // x: poly6 factor, y: spiky gradient factor (< 0), z: viscosity Laplacian
                       // factor, w: h^2
  vec4 simFluid;       // x: rest density, y: EOS stiffness (linear k or Tait B), z: gamma, w: speed of sound
  vec4 simViscosity;   // x: kinematic viscosity, y: Monaghan alpha, z: wall clamp margin,
                       // w: the walls' viscosity term over the fluid's (Scene::wallViscosityMultiple;
                       //    SIM_WALL_VISCOSITY)
  vec4 simStep;        // x: CFL factor, y: viscous factor, z: force (WCSPH) or fall (DFSPH) factor,
                       // w: fixed dt (0: CFL)
  vec4 simLimits;      // x: dt_min, y: dt_max, z: health max density, w: health max speed
  uvec4 simCounts;     // x: particles, y: boundary samples, z: colliders, w: dispatch argument entries
};

// Simulation state on the GPU. C++ mirror: sphfx::sim::SimState.
layout(std430, binding = SPHFX_SSBO_SIM_STATE) buffer SimStateBlock {
  double stateFrameEnd;  // simulated time the current frame ends at
  double stateTime;      // end of the current substep (start of the next)
  double stateDtSum;
  float stateDt;
  uint stateDone;  // 1: the frame is reached (or the run failed): later dispatches are empty
  uint stateSubsteps;
  uint stateFailure;  // SIM_FAIL_* bits
  uint stateFailSubstep;
  uint stateMaxSpeed2;  // float bits; per-substep reductions, reset by sim_timestep.comp
  uint stateMaxAccel2;
  uint stateMaxDensity;
  float stateDtLow;
  float stateDtHigh;
  // DFSPH_WARM_FLOW_LIMITED (solver.dfsph.density_warm_steps "flow_limited"), all 0 at a frame's start:
  uint stateFlowLimited;  // 1: the flow (not dt_max or the depth cap) set the last chosen step
  uint stateWarmDensity;  // after sim_timestep.comp: the value stateFlowLimited had before it
  uint stateWarmSubsteps;  // per frame: substeps whose constant-density solve started warm
  uvec4 stateHealthCount;  // per frame: non-finite, outside domain, too fast, too dense
  uvec4 stateHealthFirst;  // smallest offending particle id per cause
};

#if defined(SIM_DYNAMIC_COUNT)
uint simParamsCapacity() { return simCounts.x; }  // the particles the buffers hold (before the macro)
#include "sph_dynamic.glsl"
// Every per-particle pass loops over the live particles: simCounts.x below is the live count, while the
// uniform's own x is the capacity the buffers were sized for. (A macro does not expand inside its own
// expansion, so simCounts.yzw is the uniform's.)
#define simCounts uvec4(dynLive, simCounts.yzw)
#endif

#define SIM_FAIL_NONFINITE 1u
#define SIM_FAIL_SPEED 2u
#define SIM_FAIL_DENSITY 4u
#define SIM_FAIL_DT 8u
#define SIM_FAIL_NEIGHBORS 16u  // DFSPH: a neighbour list overflowed (set by sim_dfsph_factor.comp)
