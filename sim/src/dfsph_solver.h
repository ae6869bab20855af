#pragma once
/// @file dfsph_solver.h
/// @brief Divergence-free SPH (Bender & Koschier 2015, "Divergence-free smoothed particle hydrodynamics";
/// 2017, "Divergence-free SPH for incompressible and viscous fluids") on the GPU. Per substep, with the
/// positions of the substep start:
///   computeAccelerations: density and DFSPH factor alpha_i / rho_i (Akinci 2012 boundary samples in the
///     density and the gradient sum), the divergence solver (velocities made divergence-free), then
///     gravity and viscosity as the acceleration; max |v| for the flow-speed CFL step;
///   correctVelocities (after the time step pass chose dt): the constant-density solver adds the
///     pressure acceleration so that the predicted density rho + dt D rho/Dt reaches rest density;
///   the shared symplectic Euler integration then moves the particles.
/// Both solvers are relaxed, projected Jacobi iterations on the GPU (stiffness totals >= 0), warm-started
/// from the previous substep's stiffness totals, with the average error reduced deterministically on the GPU;
/// the GPU ends a solve by emptying its indirect dispatches, and the CPU checks that flag only every
/// kCheckEvery iterations.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dispatch_gate.h"
#include "pass_timer.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/shader_program.h"
#include "wcsph_solver.h"

namespace sphfx::sim {

/// std430 block DfsphControl (shaders/sph_dfsph.glsl): the running solve and the frame statistics,
/// index 0 the constant-density solver, 1 the divergence solver.
struct DfsphControl {
  uint32_t iteration;
  uint32_t open;
  uint32_t solves[2];
  uint32_t iterSum[2];
  uint32_t iterMax[2];
  float errorSum[2];
  float errorMax[2];
  float lastError;
  uint32_t unconverged[2];  ///< solves that stopped at max_iterations above their tolerance
  uint32_t args[18];        ///< indirect arguments of source, reduce, apply; then their live values
  float meanExcess;         ///< DFSPH_CLOSED_PERIODIC: the substep's mean density less the rest density
  uint32_t pad[2];          ///< the GL rounds the block's size up to 16 bytes
};

/// DFSPH solve statistics of the frame simulated last.
struct DfsphFrameStats {
  int solves = 0;                 ///< constant-density solves (one per substep)
  double pressureIterations = 0;  ///< mean corrections per constant-density solve
  double divergenceIterations = 0;
  int maxPressureIterations = 0, maxDivergenceIterations = 0;
  double densityError = 0;     ///< mean over the solves of the final average density error (/ rho0)
  double maxDensityError = 0;  ///< largest final average density error of a solve
  double divergenceError = 0;  ///< mean final average max(D rho/Dt, 0) / rho0 (1/s)
  double maxDivergenceError = 0;
  /// Solves that max_iterations stopped above their tolerance (constant-density, divergence).
  int unconvergedPressure = 0, unconvergedDivergence = 0;
};

class DFSPHSolver : public PressureSolver {
 public:
  /// Builds the programs (tolerances and iteration limits are compiled in) and buffers for `particles`, the
  /// scene's largest count (maxParticleCount(): emitters add to it).
  /// @throws GLError if a program does not build, or if the neighbour lists hold more texels than the
  /// context's GL_MAX_TEXTURE_BUFFER_SIZE (the solver iterations read them through a buffer texture).
  /// With solver.dfsph.walls "constraints", `boundaryEntry` is the dispatch gate's entry over the
  /// `boundarySamples` wall samples, each of which then carries a stiffness of its own.
  DFSPHSolver(const Scene& scene, const DispatchGate& gate, const ShaderDefines& defines, uint32_t particles,
              uint32_t boundaryEntry = 0, uint32_t boundarySamples = 0);
  const char* name() const override { return "dfsph"; }
  void computeAccelerations(PassTimer& timer) const override;
  void correctVelocities(PassTimer& timer) const override;
  void computeDensity(PassTimer& timer) const override;
  /// Per-frame statistics for the manifest: mean iterations, final errors and unconverged solves of
  /// both solvers; a warning for each solver whose max_iterations stopped a solve above its tolerance.
  SolverFrameReport frameReport() const override;

  /// Neighbour-list slots per particle for `scene` (DFSPH_MAX_NEIGHBORS): twice the neighbours of its
  /// densest starting lattice; a particle with more fluid neighbours stops the run (kFailNeighbors).
  static int listSlots(const Scene& scene);
  /// How many of the `boundarySamples` wall samples carry a neighbour list of their own: all with
  /// constraint walls (solver.dfsph.walls), none with push walls. Throws nothing.
  static uint32_t listedSamples(const Scene& scene, uint32_t boundarySamples);

  /// `defines` plus what sim_dfsph_factor.comp needs for `scene`: the list slots, the neighbour count
  /// below which a particle gets no divergence correction (a divergence factor of 0), the walls'
  /// spiky density weights (spikyWallScales()) and, with the spiky or Wendland C2 density, its mass
  /// scale (densityMassScale(), which the weights then take).
  static ShaderDefines factorDefines(const Scene& scene, ShaderDefines defines);
  /// `defines` plus what the four programs of one solve need (sim_dfsph_begin/source/reduce/apply):
  /// the tolerances, iteration limits, relaxation (jacobiRelaxation()), momentum and warm share of
  /// `settings`, the work groups of one pass and the dispatch gate's word for the solve.
  static ShaderDefines solveDefines(const DfsphSettings& settings, double kernelSupport,
                                    ShaderDefines defines, bool divergence, uint32_t groups,
                                    uint32_t gateWord);
  /// The largest eigenvalue of the solves' Jacobi-scaled matrix on the resting lattice at kernel support
  /// `support` (spacings): max over wavevectors k of |sum_j sin(k . d_j) grad W(d_j)|^2 / sum_j |grad
  /// W(d_j)|^2 (the matrix's Fourier symbol over its diagonal), with the gradient the solves of
  /// density_kernel `kernel` take: spiky (also for poly6) 2.81 at 2 and 6.72 at 3, Wendland C2 2.61 at 2.
  /// Throws nothing.
  static double jacobiSpectralBound(double support, DfsphDensityKernel kernel = DfsphDensityKernel::Spiky);
  /// The relaxation the solves use: solver.dfsph.jacobi_omega at the default support 2, scaled by
  /// lambda(2) / lambda(support) of the spiky gradient where that is below 1, and by the spiky gradient's
  /// lambda over the density kernel's at the support, so that every support and kernel keeps the
  /// default's omega lambda, the margin to the heavy-ball iteration's divergence (omega lambda < 2 (1 +
  /// momentum)).
  static double jacobiRelaxation(const DfsphSettings& settings, double kernelSupport);
  /// `defines` plus, with constraint walls (solver.dfsph.walls), what every DFSPH pass needs for them:
  /// DFSPH_BOUNDARY_CONSTRAINTS, the list slots (the wall entries fill them from the end), the spacing
  /// and the colliders (the samples' resting share, sim_dfsph_boundary_factor.comp), and the spiky
  /// density's pressure scale (which needs these walls; sph_dfsph.glsl). Throws nothing.
  static ShaderDefines wallDefines(const Scene& scene, ShaderDefines defines);
  /// True where the fluid fills a domain periodic along every axis (its `particles` starting lattice
  /// sites hold the domain's volume) with no colliders and a fixed particle count: the constant-density
  /// solve then targets the mean density (DFSPH_CLOSED_PERIODIC, sph_dfsph.glsl), the only level a
  /// fixed volume can hold. Throws nothing.
  static bool closedPeriodic(const Scene& scene, uint32_t particles);
  /// The source pass's residual sums (DFSPH_RESIDUAL_SLOTS, sim_dfsph_source.comp): one per work group
  /// of the `particles` where `plainDefines` reduce through shared memory (SIM_WORKGROUP_REDUCE), else
  /// one per particle. Throws nothing.
  static uint32_t residualSlots(const ShaderDefines& plainDefines, uint32_t particles);
  /// `defines` (with wallDefines()) plus what sim_dfsph_boundary_source.comp needs, in both its variants
  /// (iteration; DFSPH_BOUNDARY_APPLY): the constant-density solve's and the factor pass's defines.
  static ShaderDefines sampleSolveDefines(const Scene& scene, ShaderDefines defines);
  /// True where the scene caches the pressure (cache.attributes): DFSPH then caches each frame's mean, the
  /// pressure impulse both solves applied over the frame divided by its time (DFSPH_PRESSURE_MEAN,
  /// sim_dfsph_pressure_mean.comp), which does not depend on how the frame's steps were cut. Throws
  /// nothing.
  static bool cachesMeanPressure(const Scene& scene);
  /// `defines` plus what sim_dfsph_nonpressure.comp needs (the density solve's warm share, wall push).
  static ShaderDefines nonPressureDefines(const DfsphSettings& settings, ShaderDefines defines);

  /// The factor on the particle mass in the DFSPH density and gradient sums under solver.dfsph.
  /// density_kernel `kernel` "spiky" or "wendland_c2" (the kernel of the density, of every gradient of
  /// the solves and of the walls): the poly6 lattice sum over that kernel's at kernel support `support`
  /// (spacings), so that the resting lattice sums to the rest density (spiky 0.817, Wendland C2 0.977 at
  /// 2); the samples' weights take it too. 1 for "poly6". Throws nothing.
  static double densityMassScale(DfsphDensityKernel kernel, double support);
  /// `defines` plus, with solver.dfsph.density_kernel "wendland_c2", the kernel's switch and factors for
  /// every DFSPH pass (DFSPH_KERNEL_WENDLAND, sph_dfsph.glsl). Throws nothing.
  static ShaderDefines kernelDefines(const Scene& scene, ShaderDefines defines);
  /// Weights of the wall samples' spiky density term, by how many of the domain's walls a sample lies
  /// beyond: [0] one (faces; also every collider sample), [1] two (edges), [2] three (corners). The walls
  /// enter the DFSPH density with the spiky kernel, the kernel whose gradient the solves use, so that a
  /// particle pressed into a wall sees its density rise steeply (poly6 is flat at short range); the
  /// weights make the resting lattice (fluid and samples on one lattice of spacing d, kernel support
  /// `support` d) sum to the poly6 rest density at faces, edges and corners alike. Throws nothing.
  static std::array<double, 3> spikyWallScales(double support);

  /// Reads the statistics of the frames since the last frame start from the GPU (synchronises).
  DfsphFrameStats readFrameStats() const;

  /// The CPU looks at the GPU's convergence flag after this many queued iterations.
  static constexpr int kCheckEvery = 3;

 private:
  struct Solve {
    ShaderProgram begin, source, reduce, apply;
    /// The warm start needs an apply pass (divergence); the density solve's share is applied as an
    /// acceleration by the non-pressure pass.
    bool applyWarmStart;
  };
  Solve makeSolve(const ShaderDefines& defines, bool divergence, uint32_t gateWord) const;
  void run(const Solve& s, const char* label, PassTimer& timer) const;
  void bind() const;
  /// The step start's factor pass; at the frame's end (`frameEnd`) it also caches the frame's mean
  /// pressure where cachesMeanPressure().
  void factorPass(PassTimer& timer, bool frameEnd) const;
  void checkListFitsTextureView() const;
  void dispatch(const ShaderProgram& p, uint32_t entry, const char* label) const;
  void dispatchOverSamples(const ShaderProgram& p, const char* label) const;
  void dispatchOverWetSamples(const ShaderProgram& p, const char* label) const;
  bool open() const;

  const DispatchGate* gate_;
  /// solver.dfsph: tolerances, iteration limits, relaxation, momentum and warm-start shares (each
  /// compiled into the programs as a #define).
  DfsphSettings settings_;
  double kernelSupport_;
  std::optional<double> cappedDensityTolerance_;  ///< dfsphCappedDensityTolerance() of the scene
  uint32_t particles_, groups_;
  bool closedPeriodic_;  ///< closedPeriodic(): the partial buffer also holds the group densities
  /// The source pass's residual sums, one per work group (SIM_WORKGROUP_REDUCE) or per particle
  /// (DFSPH_RESIDUAL_SLOTS): the partial buffer's first entries; the group densities follow.
  uint32_t residualSlots_;
  ShaderDefines defines_;  ///< the scene's, wallDefines(), DFSPH_CLOSED_PERIODIC, withWallContact()
  int listSlots_;
  uint32_t boundaryEntry_, boundarySamples_;  ///< the gate's entry over the wall samples, their count
  bool boundaryConstraints_;                  ///< solver.dfsph.walls "constraints"
  /// particle_ and increment_ hold the wall samples' entries after the particles' (N + b).
  GpuBuffer particle_, increment_, warm_, partial_, control_, neighbors_, boundary_, count_;
  /// Constraint walls: the samples with fluid near them this substep (sph_dfsph.glsl, DFSPH_WET_LIST).
  GpuBuffer wet_;
  /// cachesMeanPressure() only: the frame's pressure impulse per particle id, and the pass that adds a
  /// substep's to it.
  GpuBuffer pressureImpulse_;
  ShaderProgram pressureMean_;
  ShaderProgram factor_, nonPressure_;
  /// Constraint walls only: the samples' step start, iteration and apply passes, and the pass that
  /// computes their resting shares once, in the solver's first substep (restSharePending_; scenes with
  /// colliders have no such pass: their factor pass recomputes the shares every substep).
  ShaderProgram boundaryFactor_, boundarySource_, boundaryApply_, boundaryRestShare_;
  mutable bool restSharePending_ = true;
  Solve density_, divergence_;
};

}  // namespace sphfx::sim
