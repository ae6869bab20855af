#include "wcsph_solver.h"

#include <algorithm>

#include "bindings.h"
#include "boundary_akinci2012.h"
#include "gpu_types.h"
#include "sim_shaders.h"

namespace sphfx::sim {

namespace {
ShaderDefines withNeighborList(ShaderDefines d) {
  d.set("SIM_NEIGHBOR_MASKS");
  return d;
}
}  // namespace

WCSPHSolver::WCSPHSolver(const Scene& scene, const DispatchGate& gate, const ShaderDefines& defines,
                         uint32_t boundaryEntry, uint32_t boundarySamples)
    : gate_(&gate),
      boundaryEntry_(boundaryEntry),
      density_(ShaderProgram::compute(simShaderTable(), "sim_density.comp", withNeighborList(defines))),
      boundaryPressure_(ShaderProgram::compute(simShaderTable(), "sim_boundary_pressure.comp", defines)),
      force_(ShaderProgram::compute(simShaderTable(), "sim_force.comp", withNeighborList(defines))),
      neighbors_(std::max<size_t>(maxParticleCount(scene), 1) * 18 * 4),
      boundaryPressures_(std::max<size_t>(boundarySamples, 1) * 4) {}

void WCSPHSolver::computeDensity(PassTimer& timer) const {
  timer.begin("density");
  neighbors_.bindStorage(SPHFX_SSBO_SIM_NEIGHBORS);
  density_.use();
  gate_->dispatch(DispatchGate::kParticleEntry, "sim_density.comp");
  storageBarrier();
}

void WCSPHSolver::computeAccelerations(PassTimer& timer) const {
  computeDensity(timer);
  timer.begin("boundary_pressure");
  boundaryPressures_.bindStorage(SPHFX_SSBO_SIM_BOUNDARY_PRESSURE);
  boundaryPressure_.use();
  gate_->dispatch(boundaryEntry_, "sim_boundary_pressure.comp");
  storageBarrier();
  timer.begin("force");
  force_.use();
  gate_->dispatch(DispatchGate::kParticleEntry, "sim_force.comp");
  storageBarrier();
}

}  // namespace sphfx::sim
