#pragma once
/// @file wcsph_solver.h
/// @brief The pressure solver interface, and weakly compressible SPH (Becker & Teschner 2007 with the
/// seed's linear EOS as an option): density (poly6) and EOS pressure, then symmetric pressure,
/// viscosity and gravity accelerations. A DFSPH solver (issue 7) implements the same interface and
/// reuses the grid, boundaries, integration, time stepping and caches.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dispatch_gate.h"
#include "pass_timer.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx::sim {

/// What a solver reports about the frame just simulated.
struct SolverFrameReport {
  std::vector<std::pair<std::string, double>> stats;  ///< figures for the manifest's per-frame entry
  std::vector<std::string> warnings;  ///< results the frame could not trust (a solve left unconverged)
};

/// Computes every particle's acceleration for the coming substep. When called, the simulator has bound
/// the sorted particle arrays, the fluid and boundary grids, the state and the scene constants
/// (shaders/sim_bindings.h); the solver writes SPHFX_SSBO_SIM_ACCEL and the reductions of SimState
/// (max speed^2, max acceleration^2, max density).
class PressureSolver {
 public:
  virtual ~PressureSolver() = default;
  virtual const char* name() const = 0;
  /// Queues the solver's passes (GPU work only).
  virtual void computeAccelerations(PassTimer& timer) const = 0;
  /// Only density and pressure: the cache attributes of a frame's end state (DFSPH: the frame's mean
  /// pressure, DFSPHSolver::cachesMeanPressure()) and the first frame's health check.
  virtual void computeDensity(PassTimer& timer) const = 0;
  /// Queued after the time step pass chose dt, before integration: predictor-corrector solvers (DFSPH's
  /// constant-density solve) correct the accelerations for that dt here. Default: nothing.
  virtual void correctVelocities(PassTimer& /*timer*/) const {}
  /// Solver statistics and warnings of the frame just simulated (may read back from the GPU). Default:
  /// none.
  virtual SolverFrameReport frameReport() const { return {}; }
};

class WCSPHSolver : public PressureSolver {
 public:
  /// `boundaryEntry` is the gate's dispatch over the `boundarySamples` boundary samples
  /// (BoundaryAkinci2012::gateEntry(), count()). @throws GLError if a program does not build.
  WCSPHSolver(const Scene& scene, const DispatchGate& gate, const ShaderDefines& defines,
              uint32_t boundaryEntry, uint32_t boundarySamples);
  const char* name() const override { return "wcsph"; }
  void computeAccelerations(PassTimer& timer) const override;
  void computeDensity(PassTimer& timer) const override;

 private:
  void sumWallShares() const;

  const DispatchGate* gate_;
  uint32_t boundaryEntry_, boundarySamples_;
  ShaderProgram density_, boundaryPressure_, force_;
  std::optional<ShaderProgram> wallShare_;  ///< static samples only (no colliders)
  GpuBuffer neighbors_;          ///< per particle and row of cells: which candidates are within h (18 words)
  GpuBuffer boundaryPressures_;  ///< p_b / rho_b^2 per sorted boundary sample
  GpuBuffer wallShares_;         ///< static samples: sum psi W over the samples, per sorted sample
  mutable bool wallSharesSummed_ = false;
};

}  // namespace sphfx::sim
