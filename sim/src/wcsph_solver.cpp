#include "wcsph_solver.h"

#include <algorithm>

#include "bindings.h"
#include "boundary_akinci2012.h"
#include "gpu_types.h"
#include "sim_shaders.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"

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
      boundarySamples_(boundarySamples),
      density_(ShaderProgram::compute(simShaderTable(), "sim_density.comp", withNeighborList(defines))),
      boundaryPressure_(ShaderProgram::compute(simShaderTable(), "sim_boundary_pressure.comp", defines)),
      force_(ShaderProgram::compute(
          simShaderTable(), "sim_force.comp",
          withNeighborList(withWallContact(
              scene, restWallSum(scene, [&](double r2) { return densityKernel(scene, r2); }), defines)))),
      neighbors_(std::max<size_t>(maxParticleCount(scene), 1) * 18 * 4),
      boundaryPressures_(std::max<size_t>(boundarySamples, 1) * 4) {
  if (!scene.colliders.empty()) return;
  wallShare_ = ShaderProgram::compute(simShaderTable(), "sim_boundary_pressure.comp",
                                      ShaderDefines(defines).set("BOUNDARY_WALL_SHARE"));
  wallShares_ = GpuBuffer(std::max<size_t>(boundarySamples, 1) * 4);
}

void WCSPHSolver::sumWallShares() const {
  // Not gated: the samples' order is fixed once the simulator has sorted them (before any substep).
  wallShares_.bindStorage(SPHFX_SSBO_SIM_BOUNDARY_WALL_SHARE);
  wallShare_->use();
  glDispatchCompute((boundarySamples_ + kSimWorkGroup - 1) / kSimWorkGroup, 1, 1);
  glCheck("sim_boundary_pressure.comp (BOUNDARY_WALL_SHARE)");
  storageBarrier();
  wallSharesSummed_ = true;
}

void WCSPHSolver::computeDensity(PassTimer& timer) const {
  timer.begin("density");
  neighbors_.bindStorage(SPHFX_SSBO_SIM_NEIGHBORS);
  boundaryPressures_.bindStorage(SPHFX_SSBO_SIM_BOUNDARY_PRESSURE);  // the samples' marks
  density_.use();
  gate_->dispatch(DispatchGate::kParticleEntry, "sim_density.comp");
  storageBarrier();
}

void WCSPHSolver::computeAccelerations(PassTimer& timer) const {
  computeDensity(timer);
  timer.begin("boundary_pressure");
  if (wallShare_ && !wallSharesSummed_) sumWallShares();
  if (wallShare_) wallShares_.bindStorage(SPHFX_SSBO_SIM_BOUNDARY_WALL_SHARE);
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
