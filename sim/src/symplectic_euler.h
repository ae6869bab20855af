#pragma once
/// @file symplectic_euler.h
/// @brief Time stepping shared by every solver: the GPU time step pass (fixed or CFL-adaptive dt from
/// the GPU reductions, landing exactly on frame times, per-substep health) and the symplectic Euler
/// integration with the last-resort wall and collider projection.

#include "dispatch_gate.h"
#include "pass_timer.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx::sim {

class SymplecticEuler {
 public:
  /// @throws GLError if a program does not build.
  SymplecticEuler(const DispatchGate& gate, const ShaderDefines& defines);
  /// Chooses this substep's dt (one invocation; closes the gate when the frame is reached or a check
  /// fails).
  void chooseStep(PassTimer& timer) const;
  /// v += dt a; x += dt v; clamp and project. Writes the unsorted state.
  void integrate(PassTimer& timer) const;

 private:
  const DispatchGate* gate_;
  ShaderProgram timestep_, integrate_;
};

}  // namespace sphfx::sim
