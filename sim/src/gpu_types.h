#pragma once
/// @file gpu_types.h
/// @brief C++ mirrors of the simulation's GLSL blocks (shaders/sph_params.glsl, sph_colliders.glsl),
/// and the scene-derived constants that fill them.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "sphfx/core/scene.h"
#include "sphfx/gpu/gpu_layout.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx::sim {

/// std140 uniform block SimParams: scene constants of every solver pass.
struct SimParams {
  float domainMin[4];   ///< xyz; w: kernel support radius h
  float domainMax[4];   ///< xyz; w: particle spacing
  float gravity[4];     ///< xyz; w: particle mass
  int32_t gridDims[4];  ///< xyz: cells; w: number of cells
  float kernel[4];  ///< density and gradient kernel factors (poly6/spiky or Wendland C2), viscosity Laplacian
                    ///< factor, h^2
  float fluid[4];   ///< rest density, EOS stiffness (k or Tait B), gamma, speed of sound
  float viscosity[4];  ///< kinematic viscosity, Monaghan alpha, wall clamp margin, walls' viscosity multiple
  float step[4];       ///< CFL, viscous and force factors, fixed dt (0: CFL)
  float limits[4];     ///< dt_min, dt_max, health max density, health max speed
  uint32_t counts[4];  ///< particles, boundary samples, colliders, dispatch argument entries
};

/// std430 shader storage block SimStateBlock: time, dt, per-substep reductions and health counters.
struct SimState {
  double frameEnd;
  double time;
  double dtSum;
  float dt;
  uint32_t done;
  uint32_t substeps;
  uint32_t failure;
  uint32_t failSubstep;
  uint32_t maxSpeed2;  ///< float bits
  uint32_t maxAccel2;
  uint32_t maxDensity;
  float dtLow;
  float dtHigh;
  uint32_t flowLimited;   ///< 1: the flow, not dt_max or the depth cap, set the last chosen step
  uint32_t warmDensity;   ///< stateFlowLimited before the substep's sim_timestep.comp
  uint32_t warmSubsteps;  ///< per frame: substeps whose constant-density solve started warm
  alignas(16) uint32_t healthCount[4];  ///< non-finite, outside the domain, too fast, too dense
  uint32_t healthFirst[4];              ///< smallest offending id per cause
};

/// Failure bits of SimState::failure (shaders/sph_params.glsl).
enum SimFailure : uint32_t {
  kFailNonFinite = 1,
  kFailSpeed = 2,
  kFailDensity = 4,
  kFailDt = 8,
  kFailNeighbors = 16,  ///< DFSPH: a particle had more fluid neighbours than its list holds
};

/// One element of the std430 array SimColliders::colliders[].
struct ColliderGpu {
  float shapeA[4];  ///< box: min corner; sphere: centre and radius; field: voxel (0,0,0)'s centre, voxel size
  float shapeB[4];  ///< box: max corner; field: voxel counts
  float pivot[4];   ///< xyz: the rest pivot rotations turn about (colliderPivot())
  uint32_t info[4];  ///< shape (0 box, 1 sphere, 2 field), first key, key count, field's first value
};

/// One element of the std430 array SimEmitters::emitters[] (shaders/sph_emitters.glsl).
struct EmitterGpu {
  double time[2];     ///< start (s), layer period spacing / speed (s)
  float dirSpeed[4];  ///< xyz: unit direction, w: speed
  uint32_t info[4];   ///< points per layer, first point, layers in all, 1 for a volume source
  float regionA[4];   ///< volume source: box min, or sphere centre with w = radius
  float regionB[4];   ///< volume source: box max; w: 1 box, 2 sphere (0: a disc, no region)
};

/// Normalisation factors of the kernels for support radius h (Mueller et al. 2003).
struct KernelFactors {
  double poly6;               ///< W(r) = poly6 (h^2 - r^2)^3
  double spikyGradient;       ///< grad W(r) = spikyGradient (h - r)^2 r/|r| (negative)
  double viscosityLaplacian;  ///< lap W(r) = viscosityLaplacian (h - r)
};
KernelFactors kernelFactors(double h);

/// Normalisation factors of Wendland C2 in 3D for support radius h: W(r) = density (1 - q)^4 (1 + 4 q),
/// grad W(r) = gradient (1 - q)^3 r (negative), q = |r| / h.
struct WendlandFactors {
  double density;   ///< 21 / (2 pi h^3)
  double gradient;  ///< -210 / (pi h^5)
};
WendlandFactors wendlandFactors(double h);

/// -W'(r) / r of a solver's gradient kernel at support h, 0 < r < h: Wendland C2's (`wendland`) or the
/// spiky kernel's, so grad W(d) = -gradientOverDistance(r) d. Positive. Throws nothing.
double gradientOverDistance(bool wendland, double r, double h);

/// The scene's solver uses Wendland C2 (WCSPH with solver.wcsph.kernel = wendland_c2) rather than the
/// poly6 / spiky pair.
bool usesWendland(const Scene& scene);

/// The density kernel of the scene's solver at squared distance r2 (0 beyond h).
double densityKernel(const Scene& scene, double r2);

/// The spiky kernel W(r) = -spikyGradient / 3 (h - r)^3 for support h, the kernel whose gradient the
/// shaders use (0 beyond h).
double spikyKernel(double h, double r);

/// The Wendland C2 kernel W(r) = 21 / (2 pi h^3) (1 - r / h)^4 (1 + 4 r / h) for support h (0 beyond h).
double wendlandKernel(double h, double r);

/// Neighbours within q spacings of a particle in a full cubic lattice, itself left out: 26 at q = 2.
int latticeNeighbours(double q);

/// The walls' kernel sum sum_b psi_b K(|x - x_b|^2) (kg/m^3) at a particle's site half a spacing from a
/// flat wall: the wall samples continue the fluid's lattice boundary-layers deep, each of the calibrated
/// particle mass (boundary_akinci2012.h). `kernel` takes the squared distance (m^2) and is 0 beyond h.
double restWallSum(const Scene& scene, const std::function<double(double)>& kernel);

/// `defines` plus fluid.wall_contact's, where it is above 0 (sph_kernels.glsl, sphWallContact()):
/// SIM_WALL_CONTACT, the neighbour count (fluid and samples within h) below which it acts, and
/// SIM_WALL_CONTACT_REST, `restSum`: restWallSum() with the solver's wall kernel and weights. (Its
/// collider half, SIM_COLLIDER_CONTACT, is in simShaderDefines(): WCSPH applies it in the integration.)
ShaderDefines withWallContact(const Scene& scene, double restSum, ShaderDefines defines);

/// The largest of `f` over the wavevectors k (radians per spacing) of the cubic lattice's irreducible
/// Brillouin zone on a grid of `steps` per axis, 0 <= k[0] <= k[1] <= k[2] <= pi: for a symbol that is even
/// and symmetric under the axis permutations, its largest value over every k on that grid.
double maxOverLatticeModes(int steps, const std::function<double(const std::array<double, 3>&)>& f);

/// The largest decay rate (1/s) of Monaghan's artificial viscosity (fluid.artificial_viscosity, the
/// viscosity passes' artificialViscosity()) on the resting cubic lattice: 0 for other viscosity models
/// or alpha = 0. The term is linearised with its approaching-only switch left out (the switch only drops
/// damping), a_i = -sum_j m nu F(r) r^2 / (r^2 + 0.01 h^2) (x^ x^T)(v_i - v_j) with F = -W'(r) / r of the
/// solver's gradient kernel, m the mass its sums take and nu = alpha h c / rho0, and maximised over the
/// velocity modes e exp(i k . x) of the lattice; the walls' term multiplies it by
/// max(1, Scene::wallViscosityMultiple()). An explicit step above 2 / rate lets the term amplify the mode
/// it should damp.
double artificialViscosityRate(const Scene& scene);

/// Particle mass that puts the initial cubic lattice exactly at rest density with the scene's density kernel:
/// rho0 / sum_j W(x_j) over the lattice. (The nominal rho0 spacing^3 is a few percent off at h = 2
/// spacings, which would compress or expand the fluid in the first steps.)
double calibratedParticleMass(const Scene& scene);

/// Cells of the neighbour grid over the domain (cell size h; along a periodic axis floor(extent / h)
/// cells, the last one wider, see periodicCells()).
std::array<int, 3> gridDims(const Scene& scene);

/// Most row starts (cells x gridSplitX()) of the neighbour grid per particle (maxParticleCount()): the
/// per-cell sort writes them all every build, so a sparse domain keeps whole cells.
constexpr double kGridRowStartsPerParticle = 16.0;

/// Slabs per grid cell in x that the neighbour walks resolve: 4, 2 or 1, the largest with at most
/// kGridRowStartsPerParticle row starts per initial particle; 1 along a periodic x axis. With slabs of
/// h / 4 a walk visits only the x-interval that the kernel sphere reaches in each row of cells, about
/// 15 h^3 of candidates instead of 27 h^3 (sph_kernels.glsl, sphRow(); NeighborGrid::rowStart()).
int gridSplitX(const Scene& scene);

/// The scene the wall samples are taken from (sampleBoundaries()): the scene itself, its domain widened
/// past each open face by `wallDepth` (the sample shell's depth), so that the walls adjoining an open
/// face continue past it and no wall sample lies within a kernel radius of it.
Scene wallSamplingScene(const Scene& scene, double wallDepth);

/// Distance particles are kept inside the domain walls and outside colliders by the last-resort clamp.
double clampMargin(const Scene& scene);

/// The uniform block for a scene.
SimParams makeSimParams(const Scene& scene, uint32_t particles, uint32_t boundarySamples,
                        uint32_t dispatchEntries);

/// Work group size of the per-particle passes.
constexpr int kSimWorkGroup = 64;

/// DFSPH with solver.dfsph.density_warm_steps "flow_limited" and a warm share (DFSPH_WARM_FLOW_LIMITED):
/// sim_timestep.comp records which limit set each step, and a frame reports pressure_warm_substeps.
bool dfsphWarmsFlowLimited(const Scene& scene);

/// The CFL step's upper limit (s): time.dt_max, DFSPH's depth step and the artificial viscosity's explicit
/// bound 2 / rate (WCSPH's acoustic step, ~h / c, is below that bound for alpha up to about 1).
double stepCap(const Scene& scene);

/// DFSPH's constant-density tolerance in the steps that dt_max or the artificial viscosity's bound set below
/// the depth cap (Scene::dfsphDepthStep): solver.dfsph.max_density_error x (that step / the depth step)^2,
/// so that one step's fall (g dt^2 / d) keeps its ratio to the tolerance at the depth cap, where a
/// resting column was validated; a looser tolerance lets those solves stop after a few iterations and
/// the column jitter. Empty where no such step exists (DFSPH_CAPPED_TOLERANCE; sim_timestep.comp then
/// records which limit set each step, sim_dfsph_reduce.comp reads it).
std::optional<double> dfsphCappedDensityTolerance(const Scene& scene);

/// Shader variant switches of a scene: EOS, viscosity model, colliders, periodic axes (SIM_PERIODIC_X,
/// SIM_PERIODIC_Y, SIM_PERIODIC_Z), a varying particle count (SIM_DYNAMIC_COUNT; HAS_EMITTERS,
/// SIM_OPEN_FACES bits, SIM_KILL_BOXES count). Leaves out what the scene does not use.
ShaderDefines simShaderDefines(const Scene& scene);

/// Whether the passes reduce through work-group shared memory (SIM_WORKGROUP_REDUCE, sph_group_max.glsl,
/// sim_dfsph_source.comp and the grid's scan, sim_scan_blocks.comp): on hardware GPUs, not on CPU
/// rasterisers (llvmpipe), where barriers cost more than per-invocation atomics and sums. The environment
/// variable SPHFX_WORKGROUP_REDUCE=1 or 0 forces it (tests run both paths on one device). Reads the current
/// GL context's renderer.
/// @throws InputError if SPHFX_WORKGROUP_REDUCE is set to anything else
bool workgroupReduce();

/// Whether the wall samples' per-substep passes visit every sample (SIM_VISIT_EVERY_SAMPLE), rather than
/// skipping those that no particle reached and that had no fluid near (DFSPH_SAMPLES_MARKED in
/// sph_dfsph.glsl, sim_boundary_pressure.comp), which changes no result: off unless the environment
/// variable SPHFX_VISIT_EVERY_SAMPLE is 1 (tests run both paths).
/// @throws InputError if SPHFX_VISIT_EVERY_SAMPLE is set to anything but 1 or 0
bool visitEverySample();

/// Every C++-mirrored block of the simulation stage, for the layout tests.
std::vector<GpuBlockLayout> simGpuLayouts();

}  // namespace sphfx::sim
