#include "sphfx/core/methods.h"

namespace sphfx {

const std::vector<MethodEntry<Solver>>& pressureSolverRegistry() {
  static const std::vector<MethodEntry<Solver>> registry = {
      {Solver::WCSPH, "wcsph",
       "weakly compressible SPH: pressure from an equation of state (linear, or Tait as in Becker & "
       "Teschner 2007), explicit steps under the acoustic CFL limit",
       "wcsph"},
      {Solver::DFSPH, "dfsph",
       "divergence-free SPH (Bender & Koschier 2015/2017): constant-density and divergence-free solves by "
       "relaxed Jacobi iterations, steps under a displacement bound",
       "dfsph"},
  };
  return registry;
}

const std::vector<MethodEntry<SurfaceMethod>>& surfacingMethodRegistry() {
  static const std::vector<MethodEntry<SurfaceMethod>> registry = {
      {SurfaceMethod::Spheres, "spheres",
       "union of particle spheres (OpenVDB ParticlesToLevelSet): a fast preview", ""},
      {SurfaceMethod::ZhuBridson, "zhu-bridson",
       "distance to the kernel-weighted average of nearby particles (Zhu & Bridson 2005)", ""},
      {SurfaceMethod::Anisotropic, "anisotropic",
       "anisotropic kernels from each particle's neighbourhood covariance (Yu & Turk 2013)", "anisotropic"},
  };
  return registry;
}

}  // namespace sphfx
