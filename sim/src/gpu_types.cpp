#include "gpu_types.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include "dfsph_solver.h"
#include "sphfx/core/collider_motion.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"

namespace sphfx::sim {

KernelFactors kernelFactors(double h) {
  const double pi = std::numbers::pi;
  return {315.0 / (64.0 * pi * std::pow(h, 9)), -45.0 / (pi * std::pow(h, 6)), 45.0 / (pi * std::pow(h, 6))};
}

WendlandFactors wendlandFactors(double h) {
  const double pi = std::numbers::pi;
  return {21.0 / (2.0 * pi * std::pow(h, 3)), -210.0 / (pi * std::pow(h, 5))};
}

bool usesWendland(const Scene& scene) {
  return scene.solver.method == Solver::WCSPH && scene.solver.wcsph.kernel == SphKernel::WendlandC2;
}

double densityKernel(const Scene& scene, double r2) {
  const double h = scene.kernelRadius();
  if (r2 >= h * h) return 0;
  if (usesWendland(scene)) return wendlandKernel(h, std::sqrt(r2));
  return kernelFactors(h).poly6 * std::pow(h * h - r2, 3);
}

double wendlandKernel(double h, double r) {
  const double q = r / h;
  return q < 1 ? wendlandFactors(h).density * std::pow(1 - q, 4) * (1 + 4 * q) : 0.0;
}

double spikyKernel(double h, double r) {
  return r < h ? -kernelFactors(h).spikyGradient / 3 * std::pow(h - r, 3) : 0.0;
}

int latticeNeighbours(double q) {
  const int n = int(std::ceil(q));
  int count = 0;
  for (int x = -n; x <= n; ++x)
    for (int y = -n; y <= n; ++y)
      for (int z = -n; z <= n; ++z) count += (x * x + y * y + z * z) < q * q ? 1 : 0;
  return count - 1;
}

double restWallSum(const Scene& scene, const std::function<double(double)>& kernel) {
  // The site at the origin, the wall's face half a spacing below it: the samples sit at x = -1 .. -layers
  // spacings (the same layers as sampleBoundaries()), every y and z within reach.
  const double s = scene.fluid.spacing, h = scene.kernelRadius();
  const int n = int(std::ceil(h / s)), layers = std::max(1, int(std::ceil(h / s - 1e-9)));
  double sum = 0;
  for (int x = -layers; x <= -1; ++x)
    for (int y = -n; y <= n; ++y)
      for (int z = -n; z <= n; ++z) sum += kernel(s * s * double(x * x + y * y + z * z));
  return calibratedParticleMass(scene) * sum;
}

ShaderDefines withWallContact(const Scene& scene, double restSum, ShaderDefines defines) {
  const double share = scene.fluid.wallContact;
  if (share <= 0) return defines;
  defines.set("SIM_WALL_CONTACT", float(share * latticeNeighbours(scene.solver.kernelSupport)));
  defines.set("SIM_WALL_CONTACT_REST", float(restSum));
  return defines;
}

double gradientOverDistance(bool wendland, double r, double h) {
  return wendland ? -wendlandFactors(h).gradient * std::pow(1 - r / h, 3)
                  : -kernelFactors(h).spikyGradient * (h - r) * (h - r) / r;
}

namespace {

/// The largest eigenvalue of the symmetric 3x3 matrix {xx, yy, zz, xy, xz, yz} (the trigonometric
/// closed form of the characteristic cubic's roots).
double largestEigenvalue(const std::array<double, 6>& a) {
  const double off = a[3] * a[3] + a[4] * a[4] + a[5] * a[5];
  if (off == 0) return std::max({a[0], a[1], a[2]});
  const double q = (a[0] + a[1] + a[2]) / 3;
  const double p =
      std::sqrt(((a[0] - q) * (a[0] - q) + (a[1] - q) * (a[1] - q) + (a[2] - q) * (a[2] - q) + 2 * off) / 6);
  const double b0 = (a[0] - q) / p, b1 = (a[1] - q) / p, b2 = (a[2] - q) / p;
  const double b3 = a[3] / p, b4 = a[4] / p, b5 = a[5] / p;
  const double det = b0 * (b1 * b2 - b5 * b5) - b3 * (b3 * b2 - b5 * b4) + b4 * (b3 * b5 - b1 * b4);
  const double phi = std::acos(std::clamp(det / 2, -1.0, 1.0)) / 3;
  return q + 2 * p * std::cos(phi);
}

/// A lattice site x_j within the kernel of the site at the origin, with the weight of its 3x3 matrix
/// weight x_j x_j^T in the linearised artificial term (artificialViscosityRate()).
struct ViscositySite {
  double x[3], weight;
};

/// The resting lattice's sites within h, each weighted m nu F(r) / (r^2 + 0.01 h^2), F = -W'(r) / r of the
/// solver's gradient kernel and m the mass its sums take.
std::vector<ViscositySite> artificialViscositySites(const Scene& scene) {
  const double s = scene.fluid.spacing, h = scene.kernelRadius();
  const bool dfsph = scene.solver.method == Solver::DFSPH;
  const DfsphDensityKernel densityKernel = scene.solver.dfsph.densityKernel;
  const bool wendland = dfsph ? densityKernel == DfsphDensityKernel::WendlandC2 : usesWendland(scene);
  double mass = calibratedParticleMass(scene);
  if (dfsph) mass *= DFSPHSolver::densityMassScale(densityKernel, scene.solver.kernelSupport);
  const double nu = scene.fluid.artificialViscosity * h * scene.soundSpeed() / scene.fluid.restDensity;
  std::vector<ViscositySite> sites;
  const int n = int(std::ceil(h / s));
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int l = -n; l <= n; ++l) {
        const double r2 = s * s * double(i * i + j * j + l * l);
        if (r2 == 0 || r2 >= h * h) continue;
        sites.push_back({{i * s, j * s, l * s},
                         mass * nu * gradientOverDistance(wendland, std::sqrt(r2), h) / (r2 + 0.01 * h * h)});
      }
  return sites;
}

/// The decay rate of the velocity mode of wavevector k: the largest eigenvalue of
/// sum_j weight_j (1 - cos k . x_j) x_j x_j^T.
double artificialViscosityModeRate(const std::vector<ViscositySite>& sites, const double k[3]) {
  std::array<double, 6> m{};
  for (const ViscositySite& site : sites) {
    const double* x = site.x;
    const double f = site.weight * (1 - std::cos(k[0] * x[0] + k[1] * x[1] + k[2] * x[2]));
    m[0] += f * x[0] * x[0];
    m[1] += f * x[1] * x[1];
    m[2] += f * x[2] * x[2];
    m[3] += f * x[0] * x[1];
    m[4] += f * x[0] * x[2];
    m[5] += f * x[1] * x[2];
  }
  return largestEigenvalue(m);
}

}  // namespace

double maxOverLatticeModes(int steps, const std::function<double(const std::array<double, 3>&)>& f) {
  double best = 0;
  for (int i = 0; i <= steps; ++i)
    for (int j = i; j <= steps; ++j)
      for (int l = j; l <= steps; ++l)
        best = std::max(best, f({std::numbers::pi * i / steps, std::numbers::pi * j / steps,
                                 std::numbers::pi * l / steps}));
  return best;
}

double artificialViscosityRate(const Scene& scene) {
  if (scene.fluid.viscosityModel != ViscosityModel::Artificial || scene.fluid.artificialViscosity <= 0)
    return 0;
  const std::vector<ViscositySite> sites = artificialViscositySites(scene);
  const double s = scene.fluid.spacing;
  const double rate = maxOverLatticeModes(8, [&](const std::array<double, 3>& k) {
    const double perMetre[3] = {k[0] / s, k[1] / s, k[2] / s};
    return artificialViscosityModeRate(sites, perMetre);
  });
  return rate * std::max(1.0, scene.wallViscosityMultiple());
}

double calibratedParticleMass(const Scene& scene) {
  const double s = scene.fluid.spacing, h = scene.kernelRadius();
  const int n = int(std::ceil(h / s));
  double sum = 0;
  for (int x = -n; x <= n; ++x)
    for (int y = -n; y <= n; ++y)
      for (int z = -n; z <= n; ++z) {
        const double r2 = s * s * double(x * x + y * y + z * z);
        sum += densityKernel(scene, r2);
      }
  return scene.fluid.restDensity / sum;
}

std::array<int, 3> gridDims(const Scene& scene) {
  std::array<int, 3> dims{};
  for (int a = 0; a < 3; ++a) {
    const double extent = scene.domain.max[a] - scene.domain.min[a];
    // Periodic: the cells must tile the period, so the last one takes the remainder (>= h).
    dims[a] = scene.domain.isPeriodic(a) ? periodicCells(extent, scene.kernelRadius())
                                         : std::max(1, int(std::ceil(extent / scene.kernelRadius())));
  }
  return dims;
}

int gridSplitX(const Scene& scene) {
  if (scene.domain.isPeriodic(0)) return 1;  // sphRowWrap() walks whole cells of h across the seam
  const auto d = gridDims(scene);
  const double cells = double(d[0]) * d[1] * d[2];
  const double budget = kGridRowStartsPerParticle * double(std::max<size_t>(maxParticleCount(scene), 1));
  for (int split : {4, 2})
    if (split * cells <= budget) return split;
  return 1;
}

Scene wallSamplingScene(const Scene& scene, double wallDepth) {
  Scene s = scene;
  for (int a = 0; a < 3; ++a) {
    if (scene.domain.isOpen(a, 0)) s.domain.min[a] -= wallDepth;
    if (scene.domain.isOpen(a, 1)) s.domain.max[a] += wallDepth;
  }
  return s;
}

double clampMargin(const Scene& scene) {
  return 0.05 * scene.fluid.spacing;
}

namespace {
void set4(float* dst, const Vec3d& v, double w) {
  for (int a = 0; a < 3; ++a) dst[a] = float(v[a]);
  dst[3] = float(w);
}
}  // namespace

double stepCap(const Scene& scene) {
  const double viscosityRate = artificialViscosityRate(scene);
  const double viscosityStep =
      viscosityRate > 0 ? 2 / viscosityRate : std::numeric_limits<double>::infinity();
  return std::min({scene.time.dtMax, scene.dfsphDepthStep(), viscosityStep});
}

SimParams makeSimParams(const Scene& scene, uint32_t particles, uint32_t boundarySamples,
                        uint32_t dispatchEntries) {
  SimParams p{};
  const double h = scene.kernelRadius();
  set4(p.domainMin, scene.domain.min, h);
  set4(p.domainMax, scene.domain.max, scene.fluid.spacing);
  set4(p.gravity, scene.gravity, calibratedParticleMass(scene));
  const auto dims = gridDims(scene);
  p.gridDims[0] = dims[0];
  p.gridDims[1] = dims[1];
  p.gridDims[2] = dims[2];
  p.gridDims[3] = dims[0] * dims[1] * dims[2];
  const KernelFactors k = kernelFactors(h);
  const WendlandFactors w = wendlandFactors(h);
  p.kernel[0] = float(usesWendland(scene) ? w.density : k.poly6);
  p.kernel[1] = float(usesWendland(scene) ? w.gradient : k.spikyGradient);
  p.kernel[2] = float(k.viscosityLaplacian);
  p.kernel[3] = float(h * h);
  const double rho0 = scene.fluid.restDensity, c = scene.soundSpeed();
  const WcsphSettings& wcsph = scene.solver.wcsph;
  const bool tait = wcsph.eos == EquationOfState::Tait;
  p.fluid[0] = float(rho0);
  p.fluid[1] = float(tait ? rho0 * c * c / wcsph.gamma : wcsph.stiffness);
  p.fluid[2] = float(wcsph.gamma);
  p.fluid[3] = float(c);
  p.viscosity[0] = float(scene.fluid.viscosity);
  p.viscosity[1] = float(scene.fluid.artificialViscosity);
  p.viscosity[2] = float(clampMargin(scene));
  p.viscosity[3] = float(scene.wallViscosityMultiple());
  const bool fixed = scene.time.mode == TimeStepMode::Fixed;
  p.step[0] = float(scene.time.cflFactor);
  p.step[1] = float(scene.time.viscousFactor);
  // z: the acceleration bound's factor, Monaghan's force criterion (WCSPH) or the fall bound (DFSPH).
  p.step[2] = float(scene.solver.method == Solver::DFSPH ? scene.solver.dfsph.fallFactor
                                                         : scene.solver.wcsph.forceFactor);
  p.step[3] = fixed ? float(scene.time.dt) : 0.0f;
  p.limits[0] = float(scene.time.dtMin);
  p.limits[1] = float(stepCap(scene));
  p.limits[2] = float(scene.health.maxDensityRatio * rho0);
  p.limits[3] = float(scene.health.maxSpeed);
  p.counts[0] = particles;
  p.counts[1] = boundarySamples;
  p.counts[2] = uint32_t(scene.colliders.size());
  p.counts[3] = dispatchEntries;
  return p;
}

bool dfsphWarmsFlowLimited(const Scene& scene) {
  const DfsphSettings& d = scene.solver.dfsph;
  return scene.solver.method == Solver::DFSPH && d.densityWarmShare > 0 &&
         d.densityWarmSteps == DfsphWarmSteps::FlowLimited;
}

std::optional<double> dfsphCappedDensityTolerance(const Scene& scene) {
  const double depthStep = scene.dfsphDepthStep();
  const double cap = stepCap(scene);
  if (!std::isfinite(depthStep) || !(cap < depthStep)) return std::nullopt;
  return scene.solver.dfsph.maxDensityError * (cap / depthStep) * (cap / depthStep);
}

ShaderDefines simShaderDefines(const Scene& scene) {
  ShaderDefines d;
  d.set("SIM_WG", kSimWorkGroup);
  d.set(scene.solver.wcsph.eos == EquationOfState::Tait ? "EOS_TAIT" : "EOS_LINEAR");
  if (scene.fluid.viscosityModel == ViscosityModel::Laplacian) d.set("VISCOSITY_LAPLACIAN");
  if (scene.fluid.viscosityModel == ViscosityModel::Artificial) d.set("VISCOSITY_ARTIFICIAL");
  if (scene.wallViscosityMultiple() > 0) d.set("SIM_WALL_VISCOSITY");
  if (scene.fluid.viscosityModel == ViscosityModel::Artificial && scene.fluid.wallDrag == WallDrag::Friction)
    d.set("SIM_WALL_FRICTION", float(scene.fluid.wallFriction));  // sph_kernels.glsl
  if (usesWendland(scene)) d.set("KERNEL_WENDLAND_C2");
  if (!scene.colliders.empty()) d.set("HAS_COLLIDERS");
  // fluid.wall_contact at colliders: half a spacing from the surface (sphColliderContact()).
  if (!scene.colliders.empty() && scene.fluid.wallContact > 0)
    d.set("SIM_COLLIDER_CONTACT", float(0.5 * scene.fluid.spacing));
  if (std::any_of(scene.colliders.begin(), scene.colliders.end(),
                  [](const Collider& c) { return c.isField(); }))
    d.set("HAS_FIELD_COLLIDERS");
  if (anyColliderRotates(scene)) d.set("SIM_COLLIDER_ROTATION");
  if (scene.solver.method == Solver::DFSPH) d.set("SOLVER_DFSPH");
  if (dfsphWarmsFlowLimited(scene))
    d.set("DFSPH_WARM_FLOW_LIMITED");  // sim_timestep.comp: which limit set dt
  if (const std::optional<double> tolerance = dfsphCappedDensityTolerance(scene))
    d.set("DFSPH_CAPPED_TOLERANCE", float(*tolerance));
  if (scene.domain.isPeriodic(0)) d.set("SIM_PERIODIC_X");
  if (scene.domain.isPeriodic(1)) d.set("SIM_PERIODIC_Y");
  if (scene.domain.isPeriodic(2)) d.set("SIM_PERIODIC_Z");
  if (const int split = gridSplitX(scene); split > 1) d.set("SIM_GRID_SPLIT_X", split);  // sphRow()
  if (scene.changesParticleCount()) {
    d.set("SIM_DYNAMIC_COUNT");  // the live count on the GPU (sph_dynamic.glsl)
    if (!scene.emitters.empty()) d.set("HAS_EMITTERS");
    if (std::any_of(scene.emitters.begin(), scene.emitters.end(),
                    [](const Emitter& e) { return e.shape != EmitterShape::Disc; }))
      d.set("HAS_VOLUME_SOURCES");  // sim_integrate.comp imposes their velocity inside them
    int open = 0;
    for (const DomainFace f : scene.domain.open) open |= 1 << int(f);
    if (open) d.set("SIM_OPEN_FACES", open);
    if (!scene.kill.empty()) d.set("SIM_KILL_BOXES", int(scene.kill.size()));
  }
  return d;
}

std::vector<GpuBlockLayout> simGpuLayouts() {
  GpuBlockLayout params{"SimParams", true, SPHFX_UBO_SIM_PARAMS, sizeof(SimParams), "sim_density.comp", {}};
  params.members = {SPHFX_GPU_MEMBER(SimParams, domainMin, "simDomainMin"),
                    SPHFX_GPU_MEMBER(SimParams, domainMax, "simDomainMax"),
                    SPHFX_GPU_MEMBER(SimParams, gravity, "simGravity"),
                    SPHFX_GPU_MEMBER(SimParams, gridDims, "simGridDims"),
                    SPHFX_GPU_MEMBER(SimParams, kernel, "simKernel"),
                    SPHFX_GPU_MEMBER(SimParams, fluid, "simFluid"),
                    SPHFX_GPU_MEMBER(SimParams, viscosity, "simViscosity"),
                    SPHFX_GPU_MEMBER(SimParams, step, "simStep"),
                    SPHFX_GPU_MEMBER(SimParams, limits, "simLimits"),
                    SPHFX_GPU_MEMBER(SimParams, counts, "simCounts")};
  GpuBlockLayout state{"SimStateBlock",     false, SPHFX_SSBO_SIM_STATE, sizeof(SimState),
                       "sim_timestep.comp", {}};
  state.members = {SPHFX_GPU_MEMBER(SimState, frameEnd, "stateFrameEnd"),
                   SPHFX_GPU_MEMBER(SimState, time, "stateTime"),
                   SPHFX_GPU_MEMBER(SimState, dtSum, "stateDtSum"),
                   SPHFX_GPU_MEMBER(SimState, dt, "stateDt"),
                   SPHFX_GPU_MEMBER(SimState, done, "stateDone"),
                   SPHFX_GPU_MEMBER(SimState, substeps, "stateSubsteps"),
                   SPHFX_GPU_MEMBER(SimState, failure, "stateFailure"),
                   SPHFX_GPU_MEMBER(SimState, failSubstep, "stateFailSubstep"),
                   SPHFX_GPU_MEMBER(SimState, maxSpeed2, "stateMaxSpeed2"),
                   SPHFX_GPU_MEMBER(SimState, maxAccel2, "stateMaxAccel2"),
                   SPHFX_GPU_MEMBER(SimState, maxDensity, "stateMaxDensity"),
                   SPHFX_GPU_MEMBER(SimState, dtLow, "stateDtLow"),
                   SPHFX_GPU_MEMBER(SimState, dtHigh, "stateDtHigh"),
                   SPHFX_GPU_MEMBER(SimState, flowLimited, "stateFlowLimited"),
                   SPHFX_GPU_MEMBER(SimState, warmDensity, "stateWarmDensity"),
                   SPHFX_GPU_MEMBER(SimState, warmSubsteps, "stateWarmSubsteps"),
                   SPHFX_GPU_MEMBER(SimState, healthCount, "stateHealthCount"),
                   SPHFX_GPU_MEMBER(SimState, healthFirst, "stateHealthFirst")};
  // Unsized array of structs: the block size is reported as 0 plus one element stride; members are
  // checked by offset.
  GpuBlockLayout colliders{
      "SimColliders", false, SPHFX_SSBO_SIM_COLLIDERS, 0, "sim_boundary_update.comp", {}};
  colliders.members = {SPHFX_GPU_MEMBER(ColliderGpu, shapeA, "colliders[0].shapeA"),
                       SPHFX_GPU_MEMBER(ColliderGpu, shapeB, "colliders[0].shapeB"),
                       SPHFX_GPU_MEMBER(ColliderGpu, pivot, "colliders[0].pivot"),
                       SPHFX_GPU_MEMBER(ColliderGpu, info, "colliders[0].info")};
  return {params, state, colliders};
}

namespace {
// An environment variable that forces a choice: 1 or 0, nullopt where unset.
std::optional<bool> forcedChoice(const char* name) {
  const char* forced = std::getenv(name);
  if (!forced) return std::nullopt;
  const std::string value = forced;
  if (value == "1") return true;
  if (value == "0") return false;
  throw InputError(std::string(name) + ": expected 1 or 0, got \"" + value + "\"");
}
}  // namespace

bool workgroupReduce() {
  if (const std::optional<bool> forced = forcedChoice("SPHFX_WORKGROUP_REDUCE")) return *forced;
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return renderer && !isSoftwareRenderer(renderer);
}

bool visitEverySample() {
  return forcedChoice("SPHFX_VISIT_EVERY_SAMPLE").value_or(false);
}

}  // namespace sphfx::sim
