#include "symplectic_euler.h"

#include "sim_shaders.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"

namespace sphfx::sim {

SymplecticEuler::SymplecticEuler(const DispatchGate& gate, const ShaderDefines& defines)
    : gate_(&gate),
      timestep_(ShaderProgram::compute(simShaderTable(), "sim_timestep.comp", defines)),
      integrate_(ShaderProgram::compute(simShaderTable(), "sim_integrate.comp", defines)) {}

void SymplecticEuler::chooseStep(PassTimer& timer) const {
  timer.begin("timestep");
  gate_->bind();
  timestep_.use();
  glDispatchCompute(1, 1, 1);
  glCheck("sim_timestep.comp");
  // The next passes read dt and the dispatch arguments it may have closed.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
}

void SymplecticEuler::integrate(PassTimer& timer) const {
  timer.begin("integrate");
  integrate_.use();
  gate_->dispatch(DispatchGate::kFinalEntry, "sim_integrate.comp");
  storageBarrier();
}

}  // namespace sphfx::sim
