#pragma once
/// @file simulator.h
/// @brief The GPU simulation of one scene, frame by frame, without any file I/O: particle buffers,
/// neighbour grid, boundaries, pressure solver, time stepping, health checks. Simulation (simulation.h)
/// adds caches, restart files, the manifest and progress.

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "boundary_akinci2012.h"
#include "dfsph_solver.h"
#include "dispatch_gate.h"
#include "gpu_types.h"
#include "neighbor_grid.h"
#include "pass_timer.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/sim/simulation.h"
#include "symplectic_euler.h"
#include "wcsph_solver.h"

namespace sphfx::sim {

/// The exact simulator state between frames: positions (w = id bits) and velocities in the buffer
/// order. Restoring it continues bit-identically.
struct SimulatorState {
  int frame = 0;
  std::vector<std::array<float, 4>> position;
  std::vector<std::array<float, 4>> velocity;
};

/// Builds the pressure solver the scene names over `boundary`'s samples. @throws InputError for a solver
/// this build lacks.
std::unique_ptr<PressureSolver> makePressureSolver(const Scene& scene, const DispatchGate& gate,
                                                   const ShaderDefines& defines,
                                                   const BoundaryAkinci2012& boundary);

class Simulator {
 public:
  /// Seeds the scene's particles at its start frame. Mesh and vdb colliders' distance fields are read
  /// from or cached in the shot `shotDir` (colliderFieldPath(); empty: built in memory). Needs a current
  /// GL context. @throws InputError (no particles, unsupported solver, bad collider geometry), IoError,
  /// GLError.
  explicit Simulator(const Scene& scene, const std::string& shotDir = "");

  /// Simulates from the current frame to the next one.
  /// @throws SimulationError naming the frame, the substep and the cause when a health check fails.
  FrameStats advance();

  int frame() const { return frame_; }
  /// Particles at the current frame (with emitters, kill boxes or open faces it changes frame by frame).
  uint32_t particleCount() const { return count_; }
  /// Particles the buffers hold: maxParticleCount() of the scene.
  uint32_t capacity() const { return capacity_; }
  uint32_t boundaryCount() const { return boundary_->count(); }

  /// The current frame as a cache (attributes as the scene asks). Density and pressure are those of the
  /// cached positions: when the scene caches them, advance() ends with a density pass over the frame's
  /// final state (the last substep's were computed before its integration). Downloads from the GPU.
  ParticleFrame cacheFrame() const;
  SimulatorState saveState() const;
  /// @throws InputError if the particle count differs (a scene whose count changes: exceeds the capacity).
  void restoreState(const SimulatorState& state);

  /// GPU time per pass (seconds) when timing is on.
  void enableTiming(bool on) { timer_.enable(on); }
  const std::map<std::string, double>& passSeconds() const { return timer_.seconds(); }

  /// Test access: the fluid grid after the latest substep, and the buffers it sorted into.
  const NeighborGrid& grid() const { return *grid_; }
  const GpuBuffer& sortedPositions() const { return pos_; }
  const BoundaryAkinci2012& boundary() const { return *boundary_; }

 private:
  void substep();
  void bindSolverBuffers() const;
  SimState readState() const;
  void startFrame(double t0, double t1);
  void refreshFrameDensity();
  bool cachesDensity() const;
  SimulatorState downloadState(const GpuBuffer& position, const GpuBuffer& velocity) const;
  void checkHealth(const SimState& s) const;
  std::string placeOf(const std::array<float, 4>& x) const;
  std::string whereDensest() const;
  std::string whereFastest() const;
  // A scene whose particle count changes (Scene::changesParticleCount()).
  void setUpDynamic();
  void bindDynamic() const;
  void emit() const;
  void syncEmitters() const;
  void compact();

  Scene scene_;
  uint32_t count_ = 0;
  uint32_t capacity_ = 0;
  bool dynamic_ = false;
  int frame_ = 0;
  int lastSubsteps_ = 8;
  ShaderDefines defines_;
  std::unique_ptr<DispatchGate> gate_;
  GpuBuffer params_, state_, posIn_, velIn_, pos_, vel_, density_, accel_;
  std::unique_ptr<NeighborGrid> grid_;
  std::unique_ptr<BoundaryAkinci2012> boundary_;
  std::unique_ptr<PressureSolver> solver_;
  std::unique_ptr<SymplecticEuler> stepper_;
  ShaderProgram health_;
  GpuBuffer dynamicState_, emitters_, emitterPoints_, killBoxes_;  // sph_dynamic.glsl, sph_emitters.glsl
  ShaderProgram emit_, emitCommit_;
  uint32_t emitterPointCount_ = 0;
  mutable PassTimer timer_;
};

}  // namespace sphfx::sim
