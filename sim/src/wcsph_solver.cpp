#include "sphfx/sim/wcsph_solver.h"

namespace sphfx::sim {

WCSPHSolver::WCSPHSolver(const Scene&, const DispatchGate& gate, const ShaderDefines& defines)
    : gate_(&gate),
      density_(ShaderProgram::compute("sim_density.comp", defines)),
      force_(ShaderProgram::compute("sim_force.comp", defines)) {}

void WCSPHSolver::computeDensity(PassTimer& timer) const {
  timer.begin("density");
  density_.use();
  gate_->dispatch(DispatchGate::kParticleEntry, "sim_density.comp");
  storageBarrier();
}

void WCSPHSolver::computeAccelerations(PassTimer& timer) const {
  computeDensity(timer);
  timer.begin("force");
  force_.use();
  gate_->dispatch(DispatchGate::kParticleEntry, "sim_force.comp");
  storageBarrier();
}

}  // namespace sphfx::sim
