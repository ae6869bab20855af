#include "dfsph_solver.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>

#include "bindings.h"
#include "gpu_types.h"
#include "sim_shaders.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"

namespace sphfx::sim {
namespace {

constexpr uint32_t kSourceEntry = 0, kReduceEntry = 1, kApplyEntry = 2;
// std430 mirror of DfsphControl: scalars and uint/float arrays pack at 4 bytes.
static_assert(offsetof(DfsphControl, lastError) == 48 && offsetof(DfsphControl, args) == 60 &&
              sizeof(DfsphControl) == 144);

// Kernel sums over a cubic lattice, in units of the spacing, around the site at the origin with the
// shaders' kernels at support `support` (poly6, spikyKernel() and wendlandKernel()), split by class: how
// many of the planes x, y, z < 0 (the first `walls` of them, the walls next to the site (0.5, 0.5, 0.5))
// a site lies beyond.
struct LatticeSums {
  std::array<double, 4> poly6{}, spiky{}, wendland{};
};

LatticeSums latticeSums(double support, int walls) {
  const double h = support, h2 = h * h;
  const KernelFactors k = kernelFactors(h);
  const int n = int(std::ceil(h)) + 1;
  LatticeSums s;
  for (int x = -n; x <= n; ++x)
    for (int y = -n; y <= n; ++y)
      for (int z = -n; z <= n; ++z) {
        const size_t cls = size_t((walls > 0 && x < 0) + (walls > 1 && y < 0) + (walls > 2 && z < 0));
        const double r2 = double(x * x + y * y + z * z), r = std::sqrt(r2);
        s.poly6[cls] += r2 < h2 ? k.poly6 * std::pow(h2 - r2, 3) : 0.0;
        s.spiky[cls] += spikyKernel(h, r);
        s.wendland[cls] += wendlandKernel(h, r);
      }
  return s;
}

// The density solve's warm share and the walls' weight in it, which the non-pressure pass applies too.
// Constraint walls push a particle with 1 x its own stiffness (its constraint's gradient).
ShaderDefines withDensitySolveShares(const DfsphSettings& s, ShaderDefines d) {
  d.set("DFSPH_DENSITY_WARM_SHARE", float(s.densityWarmShare));
  d.set("DFSPH_DENSITY_WALL_PUSH", s.walls == DfsphWalls::Constraints ? 1.0f : float(s.densityWallPush));
  return d;
}

// The walls' kernel sum over a resting particle half a spacing from a flat wall (fluid.wall_contact),
// as the factor pass sums it: psi_b times the face samples' weight times the DFSPH kernel's W.
double wallContactRest(const Scene& scene) {
  const double h = scene.kernelRadius();
  const DfsphDensityKernel kernel = scene.solver.dfsph.densityKernel;
  const double face = kernel == DfsphDensityKernel::Poly6
                          ? DFSPHSolver::spikyWallScales(scene.solver.kernelSupport)[0]
                          : DFSPHSolver::densityMassScale(kernel, scene.solver.kernelSupport);
  if (kernel == DfsphDensityKernel::WendlandC2)
    return face * restWallSum(scene, [&](double r2) { return wendlandKernel(h, std::sqrt(r2)); });
  return face * restWallSum(scene, [&](double r2) { return spikyKernel(h, std::sqrt(r2)); });
}

// Vec4 blocks of the per-particle boundary buffer (sph_dfsph.glsl): the walls' sums, fluid.wall_contact's
// excess, with colliders their contact constraint.
size_t boundaryBlocks(const Scene& scene) {
  if (!(scene.fluid.wallContact > 0)) return 1;
  return scene.colliders.empty() ? 2 : 3;
}

// Where the samples' rest shares take the resting lattice from the max wall rather than the min one
// (sim_dfsph_boundary_factor.comp, restLatticeFrame()), per axis: past the middle on an axis walled at
// both faces whose extent is not a whole number of spacings, else never (1e30). Empty where every axis
// fits.
std::optional<std::array<double, 3>> restMirrorFrom(const Scene& scene) {
  constexpr double kNever = 1e30;
  std::array<double, 3> from{kNever, kNever, kNever};
  bool any = false;
  for (int a = 0; a < 3; ++a) {
    const double lo = scene.domain.min[a], hi = scene.domain.max[a], n = (hi - lo) / scene.fluid.spacing;
    if (scene.domain.isPeriodic(a) || scene.domain.isOpen(a, 0) || scene.domain.isOpen(a, 1) ||
        std::fabs(n - std::round(n)) <= 1e-6)
      continue;
    from[size_t(a)] = 0.5 * (lo + hi);
    any = true;
  }
  return any ? std::optional(from) : std::nullopt;
}

// A particle with fewer than solver.dfsph.free_surface_fraction of a full neighbourhood is at the free
// surface; its divergence estimate is skipped.
double minNeighbours(const Scene& scene) {
  return scene.solver.dfsph.freeSurfaceFraction * latticeNeighbours(scene.solver.kernelSupport);
}

}  // namespace

bool DFSPHSolver::cachesMeanPressure(const Scene& scene) {
  return scene.solver.method == Solver::DFSPH && scene.hasCacheAttribute(CacheAttribute::Pressure);
}

ShaderDefines DFSPHSolver::factorDefines(const Scene& scene, ShaderDefines d) {
  d = withDensitySolveShares(scene.solver.dfsph, std::move(d));
  d.set("DFSPH_MAX_NEIGHBORS", listSlots(scene));
  d.set("DFSPH_MIN_NEIGHBOURS", float(minNeighbours(scene)));
  std::array<double, 3> wall = spikyWallScales(scene.solver.kernelSupport);
  if (scene.solver.dfsph.densityKernel != DfsphDensityKernel::Poly6) {
    // Fluid and samples on one lattice under one kernel: every class takes the mass scale.
    const double scale = densityMassScale(scene.solver.dfsph.densityKernel, scene.solver.kernelSupport);
    d.set("DFSPH_KERNEL_DENSITY", float(scale));
    wall = {scale, scale, scale};
  }
  if (cachesMeanPressure(scene))
    d.set("DFSPH_PRESSURE_MEAN").set("DFSPH_FRAME_SECONDS", fmt::format("{:.9g}", 1.0 / scene.time.fps));
  d.set("DFSPH_WALL_SPIKY_FACE", float(wall[0]));
  d.set("DFSPH_WALL_SPIKY_EDGE", float(wall[1]));
  d.set("DFSPH_WALL_SPIKY_CORNER", float(wall[2]));
  return d;
}

std::array<double, 3> DFSPHSolver::spikyWallScales(double support) {
  // Each class is fixed by the first site that sees it, given the classes before it. Kernel
  // normalisations cancel in the ratios except between the two kernels.
  std::array<double, 3> c{};
  for (int cls = 1; cls <= 3; ++cls) {
    const LatticeSums s = latticeSums(support, cls);
    double rest = s.poly6[size_t(cls)];
    for (int j = 1; j < cls; ++j) rest += s.poly6[size_t(j)] - c[size_t(j - 1)] * s.spiky[size_t(j)];
    c[size_t(cls - 1)] = rest / s.spiky[size_t(cls)];
  }
  return c;
}

double DFSPHSolver::densityMassScale(DfsphDensityKernel kernel, double support) {
  if (kernel == DfsphDensityKernel::Poly6) return 1.0;
  const LatticeSums s = latticeSums(support, 0);  // a full lattice: every site in class 0
  return s.poly6[0] / (kernel == DfsphDensityKernel::WendlandC2 ? s.wendland[0] : s.spiky[0]);
}

ShaderDefines DFSPHSolver::kernelDefines(const Scene& scene, ShaderDefines d) {
  if (scene.solver.dfsph.densityKernel != DfsphDensityKernel::WendlandC2) return d;
  const WendlandFactors w = wendlandFactors(scene.kernelRadius());
  return d.set("DFSPH_KERNEL_WENDLAND")
      .set("DFSPH_WENDLAND_W", float(w.density))
      .set("DFSPH_WENDLAND_GRAD", float(w.gradient));
}

uint32_t DFSPHSolver::listedSamples(const Scene& scene, uint32_t boundarySamples) {
  return scene.solver.dfsph.walls == DfsphWalls::Constraints ? boundarySamples : 0;
}

int DFSPHSolver::listSlots(const Scene& scene) {
  // Twice the mean neighbour count of a disordered fluid at the scene's densest start (4/3 pi q^3 per
  // spacing^3; the cubic lattice has fewer: 26 at q = 2, which was too tight for a 10 m/s impact at
  // dt = 0.016 s). The solver keeps densities within a few per cent, so 2x covers local clustering.
  const double q = scene.solver.kernelSupport / std::min(1.0, scene.fluid.packing);
  const double mean = std::max(double(latticeNeighbours(q)), 4.0 / 3.0 * std::numbers::pi * q * q * q);
  return std::max(32, int(std::ceil(2 * mean)));
}

ShaderDefines DFSPHSolver::wallDefines(const Scene& scene, ShaderDefines d) {
  if (scene.solver.dfsph.walls != DfsphWalls::Constraints) return d;
  d.set("DFSPH_BOUNDARY_CONSTRAINTS");
  d.set("DFSPH_MAX_NEIGHBORS", listSlots(scene));  // the apply and non-pressure passes read wall entries
  d.set("DFSPH_SPACING", float(scene.fluid.spacing));
  if (scene.solver.dfsph.densityKernel != DfsphDensityKernel::Poly6)  // (it needs these walls)
    d.set("DFSPH_PRESSURE_SCALE",
          float(densityMassScale(scene.solver.dfsph.densityKernel, scene.solver.kernelSupport)));
  // The samples' rest shares (sim_dfsph_boundary_factor.comp): lattice sites up to this many spacings out.
  d.set("DFSPH_REST_REACH", int(std::ceil(scene.solver.kernelSupport - 1e-9)));
  if (!scene.colliders.empty())  // recomputed every substep
    d.set("DFSPH_COLLIDERS", int(scene.colliders.size()));
  else if (const auto from = restMirrorFrom(scene))
    d.set("DFSPH_REST_MIRROR_FROM",
          fmt::format("vec3({:.9g}, {:.9g}, {:.9g})", (*from)[0], (*from)[1], (*from)[2]));
  return d;
}

bool DFSPHSolver::closedPeriodic(const Scene& scene, uint32_t particles) {
  if (scene.domain.periodic.size() < 3 || !scene.colliders.empty() || scene.changesParticleCount())
    return false;
  const double x = scene.domain.max[0] - scene.domain.min[0], y = scene.domain.max[1] - scene.domain.min[1],
               z = scene.domain.max[2] - scene.domain.min[2], d = scene.fluid.spacing;
  // A missing layer of sites along any axis leaves a free surface: allow less than half of one.
  const double layer = 0.5 * d * std::max({x * y, y * z, x * z});
  return double(particles) * d * d * d >= x * y * z - layer;
}

namespace {
// Work groups of the per-particle passes over `particles` (at least one).
uint32_t particleGroups(uint32_t particles) {
  return std::max<uint32_t>(1, (particles + kSimWorkGroup - 1) / kSimWorkGroup);
}

// The defines every DFSPH pass shares: the kernel's, the walls', and in a closed periodic domain its
// switch and the factor pass's work groups (DFSPHSolver::closedPeriodic).
ShaderDefines sharedDefines(const Scene& scene, const ShaderDefines& plainDefines, bool closedPeriodic,
                            uint32_t groups) {
  ShaderDefines d = DFSPHSolver::wallDefines(scene, DFSPHSolver::kernelDefines(scene, plainDefines));
  if (closedPeriodic) d.set("DFSPH_CLOSED_PERIODIC").set("DFSPH_GROUPS", groups);
  return d;
}
}  // namespace

uint32_t DFSPHSolver::residualSlots(const ShaderDefines& plainDefines, uint32_t particles) {
  return plainDefines.has("SIM_WORKGROUP_REDUCE") ? particleGroups(particles)
                                                  : std::max<uint32_t>(particles, 1);
}

ShaderDefines DFSPHSolver::sampleSolveDefines(const Scene& scene, ShaderDefines d) {
  return factorDefines(
      scene, solveDefines(scene.solver.dfsph, scene.solver.kernelSupport, std::move(d), false, 1, 0));
}

DFSPHSolver::DFSPHSolver(const Scene& scene, const DispatchGate& gate, const ShaderDefines& plainDefines,
                         uint32_t particles, uint32_t boundaryEntry, uint32_t boundarySamples)
    : gate_(&gate),
      settings_(scene.solver.dfsph),
      kernelSupport_(scene.solver.kernelSupport),
      cappedDensityTolerance_(dfsphCappedDensityTolerance(scene)),
      particles_(particles),
      groups_(particleGroups(particles)),
      closedPeriodic_(closedPeriodic(scene, particles)),
      residualSlots_(residualSlots(plainDefines, particles)),
      defines_(withWallContact(scene, wallContactRest(scene),
                               sharedDefines(scene, plainDefines, closedPeriodic_, groups_))
                   .set("DFSPH_RESIDUAL_SLOTS", residualSlots_)),
      listSlots_(listSlots(scene)),
      boundaryEntry_(boundaryEntry),
      boundarySamples_(boundarySamples),
      boundaryConstraints_(settings_.walls == DfsphWalls::Constraints),
      particle_(size_t(std::max<uint32_t>(particles + boundarySamples, 1)) * 16),
      increment_(size_t(std::max<uint32_t>(particles + boundarySamples, 1)) * 4),
      warm_(size_t(std::max<uint32_t>(particles, 1)) * 4),
      partial_((size_t(residualSlots_) + (closedPeriodic_ ? groups_ : 0)) * 4),
      control_(sizeof(DfsphControl)),
      // One spare slot: sim_dfsph_factor.comp writes every candidate to the slot after the last neighbour.
      // Constraint walls: the samples' lists and counts follow the particles' (sph_dfsph.glsl).
      neighbors_(size_t(std::max<uint32_t>(particles + listedSamples(scene, boundarySamples), 1)) * 16 *
                 size_t(listSlots_ + 1)),
      // fluid.wall_contact: a second vec4 per particle after the first N, with colliders a third
      // (sph_dfsph.glsl).
      boundary_(size_t(std::max<uint32_t>(particles, 1)) * 16 * boundaryBlocks(scene)),
      count_(size_t(std::max<uint32_t>(particles + listedSamples(scene, boundarySamples), 1)) * 4),
      factor_(
          ShaderProgram::compute(simShaderTable(), "sim_dfsph_factor.comp", factorDefines(scene, defines_))),
      nonPressure_(ShaderProgram::compute(simShaderTable(), "sim_dfsph_nonpressure.comp",
                                          nonPressureDefines(settings_, defines_))) {
  if (boundaryConstraints_) {
    wet_ = GpuBuffer((4 + size_t(std::max<uint32_t>(boundarySamples, 1))) * 4);
    const ShaderDefines factor = factorDefines(scene, defines_);
    boundaryFactor_ = ShaderProgram::compute(simShaderTable(), "sim_dfsph_boundary_factor.comp", factor);
    restSharePending_ = scene.colliders.empty();  // with colliders the factor pass computes them
    if (restSharePending_)
      boundaryRestShare_ = ShaderProgram::compute(simShaderTable(), "sim_dfsph_boundary_factor.comp",
                                                  ShaderDefines(factor).set("DFSPH_BOUNDARY_REST_SHARE"));
    const ShaderDefines d = sampleSolveDefines(scene, defines_);
    boundarySource_ = ShaderProgram::compute(simShaderTable(), "sim_dfsph_boundary_source.comp", d);
    boundaryApply_ = ShaderProgram::compute(simShaderTable(), "sim_dfsph_boundary_source.comp",
                                            ShaderDefines(d).set("DFSPH_BOUNDARY_APPLY"));
  }
  if (cachesMeanPressure(scene)) {
    pressureImpulse_ = GpuBuffer(size_t(std::max<uint32_t>(particles, 1)) * 4);
    pressureImpulse_.fill(0);
    pressureMean_ = ShaderProgram::compute(simShaderTable(), "sim_dfsph_pressure_mean.comp",
                                           factorDefines(scene, defines_));
  }
  checkListFitsTextureView();
  density_ = makeSolve(defines_, false, 0);
  divergence_ = makeSolve(defines_, true, 3 * DispatchGate::kParticleEntry);
  DfsphControl c{};
  const uint32_t live[9] = {groups_, 1, 1, 1, 1, 1, groups_, 1, 1};
  std::copy(live, live + 9, c.args + 9);
  control_.upload(&c, sizeof c);
  warm_.fill(0);
  particle_.fill(0);
}

ShaderDefines DFSPHSolver::solveDefines(const DfsphSettings& settings, double kernelSupport, ShaderDefines d,
                                        bool divergence, uint32_t groups, uint32_t gateWord) {
  d = withDensitySolveShares(settings, std::move(d));
  if (divergence) d.set("DFSPH_DIVERGENCE");
  d.set("DFSPH_SOLVE", divergence ? 1 : 0);
  d.set("DFSPH_TOLERANCE", float(divergence ? settings.maxDivergenceError : settings.maxDensityError));
  d.set("DFSPH_MIN_ITER", divergence ? settings.minDivergenceIterations : settings.minIterations);
  d.set("DFSPH_MAX_ITER", settings.maxIterations);
  d.set("DFSPH_GROUPS", groups);
  d.set("DFSPH_GATE_WORD", gateWord);
  d.set("DFSPH_OMEGA", float(jacobiRelaxation(settings, kernelSupport)));
  if (settings.jacobiMomentum > 0) d.set("DFSPH_MOMENTUM");
  d.set("DFSPH_WARM_SHARE", float(divergence ? settings.divergenceWarmShare : settings.densityWarmShare));
  return d;
}

double DFSPHSolver::jacobiSpectralBound(double support, DfsphDensityKernel kernel) {
  // Neighbour offsets d_j (in spacings) with the solves' gradients (the spiky kernel's for the poly6
  // density too); constant factors cancel in the ratio.
  const bool wendland = kernel == DfsphDensityKernel::WendlandC2;
  std::vector<std::array<double, 6>> nbr;  // d, grad W
  const int n = int(std::ceil(support));
  double diagonal = 0;
  for (int x = -n; x <= n; ++x)
    for (int y = -n; y <= n; ++y)
      for (int z = -n; z <= n; ++z) {
        const double r = std::sqrt(double(x * x + y * y + z * z));
        if (r <= 0 || r >= support) continue;
        const double g = gradientOverDistance(wendland, r, support);
        nbr.push_back({double(x), double(y), double(z), g * x, g * y, g * z});
        diagonal += g * g * r * r;
      }
  // The symbol is even and symmetric under the lattice's axis permutations.
  return maxOverLatticeModes(12, [&](const std::array<double, 3>& k) {
    double s[3] = {0, 0, 0};
    for (const auto& e : nbr) {
      const double w = std::sin(k[0] * e[0] + k[1] * e[1] + k[2] * e[2]);
      s[0] += w * e[3], s[1] += w * e[4], s[2] += w * e[5];
    }
    return (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]) / diagonal;
  });
}

double DFSPHSolver::jacobiRelaxation(const DfsphSettings& settings, double kernelSupport) {
  constexpr double kDefaultSupport = 2;  // where solver.dfsph.jacobi_omega's default was chosen
  const double spiky = jacobiSpectralBound(kernelSupport, DfsphDensityKernel::Spiky);
  const double supportScale =
      std::min(1.0, jacobiSpectralBound(kDefaultSupport, DfsphDensityKernel::Spiky) / spiky);
  return settings.jacobiOmega * supportScale * spiky /
         jacobiSpectralBound(kernelSupport, settings.densityKernel);
}

ShaderDefines DFSPHSolver::nonPressureDefines(const DfsphSettings& settings, ShaderDefines defines) {
  return withDensitySolveShares(settings, std::move(defines));
}

DFSPHSolver::Solve DFSPHSolver::makeSolve(const ShaderDefines& defines, bool divergence,
                                          uint32_t gateWord) const {
  const ShaderDefines d = solveDefines(settings_, kernelSupport_, defines, divergence, groups_, gateWord);
  return {ShaderProgram::compute(simShaderTable(), "sim_dfsph_begin.comp", d),
          ShaderProgram::compute(simShaderTable(), "sim_dfsph_source.comp", d),
          ShaderProgram::compute(simShaderTable(), "sim_dfsph_reduce.comp", d),
          ShaderProgram::compute(simShaderTable(), "sim_dfsph_apply.comp", d), divergence};
}

// The iterations read the lists through a buffer texture (sph_dfsph.glsl), whose size is limited in
// texels; say so by name before the first substep rather than from a bind inside it.
void DFSPHSolver::checkListFitsTextureView() const {
  const size_t limit = maxTextureBufferTexels(), texels = neighbors_.size() / 16;
  const size_t samples = texels / size_t(listSlots_ + 1) - std::min<size_t>(particles_, texels);
  if (texels > limit)
    throw GLError(
        fmt::format("the DFSPH neighbour lists need {} texels ({} particles and {} wall samples x {} "
                    "slots), more than this GL's GL_MAX_TEXTURE_BUFFER_SIZE ({}): use fewer particles, "
                    "fluid.packing 1 (fewer slots), or solver.method \"wcsph\" (no lists)",
                    texels, particles_, samples, listSlots_ + 1, limit));
}

void DFSPHSolver::bind() const {
  particle_.bindStorage(SPHFX_SSBO_SIM_DFSPH_PARTICLE);
  increment_.bindStorage(SPHFX_SSBO_SIM_DFSPH_INCREMENT);
  warm_.bindStorage(SPHFX_SSBO_SIM_DFSPH_WARM);
  partial_.bindStorage(SPHFX_SSBO_SIM_DFSPH_PARTIAL);
  control_.bindStorage(SPHFX_SSBO_SIM_DFSPH_CONTROL);
  neighbors_.bindStorage(SPHFX_SSBO_SIM_DFSPH_NEIGHBORS);
  neighbors_.bindTexture(SPHFX_TEX_SIM_DFSPH_NEIGHBORS, GL_RGBA32F);
  increment_.bindTexture(SPHFX_TEX_SIM_DFSPH_INCREMENT, GL_R32F);
  particle_.bindTexture(SPHFX_TEX_SIM_DFSPH_PARTICLE, GL_RGBA32F);
  count_.bindTexture(SPHFX_TEX_SIM_DFSPH_COUNT, GL_R32UI);
  boundary_.bindTexture(SPHFX_TEX_SIM_DFSPH_BOUNDARY, GL_RGBA32F);
  boundary_.bindStorage(SPHFX_SSBO_SIM_DFSPH_BOUNDARY);
  count_.bindStorage(SPHFX_SSBO_SIM_DFSPH_COUNT);
  if (boundaryConstraints_) wet_.bindStorage(SPHFX_SSBO_SIM_DFSPH_WET);
  if (pressureImpulse_.size()) pressureImpulse_.bindStorage(SPHFX_SSBO_SIM_DFSPH_PRESSURE_IMPULSE);
}

void DFSPHSolver::dispatch(const ShaderProgram& p, uint32_t entry, const char* label) const {
  p.use();
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, control_.id());
  glDispatchComputeIndirect(GLintptr(offsetof(DfsphControl, args) + entry * 12));
  glCheck(label);
  storageBarrier();
}

// A direct dispatch over every wall sample (not through the gate's entry over the samples, which may be
// closed in this substep).
void DFSPHSolver::dispatchOverSamples(const ShaderProgram& p, const char* label) const {
  p.use();
  glDispatchCompute((boundarySamples_ + kSimWorkGroup - 1) / kSimWorkGroup, 1, 1);
  glCheck(label);
  storageBarrier();
}

// An indirect dispatch over the wet list that sim_dfsph_boundary_factor.comp built this substep (not
// through the gate: its entry over the samples is closed in a frame's last substep, whose
// constant-density solve still runs); the shader reads the solve's open flag itself.
void DFSPHSolver::dispatchOverWetSamples(const ShaderProgram& p, const char* label) const {
  p.use();
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, wet_.id());
  glDispatchComputeIndirect(0);
  glCheck(label);
  storageBarrier();
}

bool DFSPHSolver::open() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  uint32_t flag = 0;
  control_.download(&flag, sizeof flag, offsetof(DfsphControl, open));
  return flag != 0;
}

void DFSPHSolver::computeDensity(PassTimer& timer) const {
  factorPass(timer, true);
}

void DFSPHSolver::factorPass(PassTimer& timer, bool frameEnd) const {
  timer.begin("dfsph_factor");
  bind();
  factor_.use();
  if (pressureImpulse_.size())
    glProgramUniform1ui(factor_.id(), factor_.uniform("uFrameEnd"), frameEnd ? 1 : 0);
  gate_->dispatch(DispatchGate::kParticleEntry, "sim_dfsph_factor.comp");
  storageBarrier();
  if (boundaryConstraints_) {
    // Directly dispatched: the gate's sample entry may be closed in this substep (a frame's last).
    if (restSharePending_)
      dispatchOverSamples(boundaryRestShare_, "sim_dfsph_boundary_factor.comp (rest share)");
    restSharePending_ = false;
    // An empty wet list: no work groups (x), 1, 1, count 0.
    const uint32_t zero = 0, one = 1;
    glClearNamedBufferSubData(wet_.id(), GL_R32UI, 0, 16, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glClearNamedBufferSubData(wet_.id(), GL_R32UI, 4, 8, GL_RED_INTEGER, GL_UNSIGNED_INT, &one);
    timer.begin("dfsph_boundary_factor");
    boundaryFactor_.use();
    gate_->dispatch(boundaryEntry_, "sim_dfsph_boundary_factor.comp");
    storageBarrier();
    glMemoryBarrier(GL_COMMAND_BARRIER_BIT);  // the wet list's dispatch arguments
  }
}

// One solve: open it (only if the substep is alive), warm start, then iterations of residual, GPU
// reduction with the convergence decision, and correction. The CPU queues kCheckEvery iterations at a
// time and stops once the GPU has closed the solve.
void DFSPHSolver::run(const Solve& s, const char* label, PassTimer& timer) const {
  timer.begin(label);
  bind();
  gate_->bind();
  s.begin.use();
  glDispatchCompute(1, 1, 1);
  glCheck("sim_dfsph_begin.comp");
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
  const GLint warm = s.source.uniform("uWarm");
  glProgramUniform1ui(s.source.id(), warm, 1u);
  dispatch(s.source, kSourceEntry, "sim_dfsph_source.comp");
  if (s.applyWarmStart) dispatch(s.apply, kApplyEntry, "sim_dfsph_apply.comp");
  glProgramUniform1ui(s.source.id(), warm, 0u);
  // The first iteration has no increment of its own to carry on (the buffer holds the warm start).
  const GLint momentum = settings_.jacobiMomentum > 0 ? s.source.uniform("uMomentum") : -1;
  glProgramUniform1f(s.source.id(), momentum, 0.0f);
  // settings_.maxIterations + 1 reductions: the last one records a solve that ran out of iterations.
  for (int it = 0; it <= settings_.maxIterations;) {
    for (int k = 0; k < kCheckEvery && it <= settings_.maxIterations; ++k, ++it) {
      dispatch(s.source, kSourceEntry, "sim_dfsph_source.comp");
      const bool wallConstraints = boundaryConstraints_ && !s.applyWarmStart;  // the density solve's
      if (wallConstraints) dispatchOverWetSamples(boundarySource_, "sim_dfsph_boundary_source.comp");
      if (it == 0) glProgramUniform1f(s.source.id(), momentum, float(settings_.jacobiMomentum));
      dispatch(s.reduce, kReduceEntry, "sim_dfsph_reduce.comp");
      glMemoryBarrier(GL_COMMAND_BARRIER_BIT);
      dispatch(s.apply, kApplyEntry, "sim_dfsph_apply.comp");
      if (wallConstraints) dispatchOverWetSamples(boundaryApply_, "sim_dfsph_boundary_source.comp (apply)");
    }
    if (!open()) break;
  }
}

void DFSPHSolver::computeAccelerations(PassTimer& timer) const {
  factorPass(timer, false);
  run(divergence_, "dfsph_divergence", timer);
  timer.begin("dfsph_nonpressure");
  nonPressure_.use();
  gate_->dispatch(DispatchGate::kParticleEntry, "sim_dfsph_nonpressure.comp");
  storageBarrier();
}

void DFSPHSolver::correctVelocities(PassTimer& timer) const {
  run(density_, "dfsph_density", timer);
  if (!pressureImpulse_.size()) return;
  timer.begin("dfsph_pressure_mean");
  pressureMean_.use();
  gate_->dispatch(DispatchGate::kFinalEntry, "sim_dfsph_pressure_mean.comp");  // open in a frame's last step
  storageBarrier();
}

DfsphFrameStats DFSPHSolver::readFrameStats() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  DfsphControl c{};
  control_.download(&c, sizeof c);
  DfsphFrameStats f;
  f.solves = int(c.solves[0]);
  auto mean = [](double sum, uint32_t n) { return n ? sum / n : 0.0; };
  f.pressureIterations = mean(c.iterSum[0], c.solves[0]);
  f.divergenceIterations = mean(c.iterSum[1], c.solves[1]);
  f.maxPressureIterations = int(c.iterMax[0]);
  f.maxDivergenceIterations = int(c.iterMax[1]);
  f.densityError = mean(c.errorSum[0], c.solves[0]);
  f.maxDensityError = c.errorMax[0];
  f.divergenceError = mean(c.errorSum[1], c.solves[1]);
  f.maxDivergenceError = c.errorMax[1];
  f.unconvergedPressure = int(c.unconverged[0]);
  f.unconvergedDivergence = int(c.unconverged[1]);
  return f;
}

SolverFrameReport DFSPHSolver::frameReport() const {
  const DfsphFrameStats f = readFrameStats();
  SolverFrameReport r;
  r.stats = {{"pressure_iterations_mean", f.pressureIterations},
             {"pressure_iterations_max", f.maxPressureIterations},
             {"divergence_iterations_mean", f.divergenceIterations},
             {"divergence_iterations_max", f.maxDivergenceIterations},
             {"density_error_mean", f.densityError},
             {"density_error_max", f.maxDensityError},
             {"divergence_error_mean", f.divergenceError},
             {"divergence_error_max", f.maxDivergenceError},
             {"pressure_unconverged", f.unconvergedPressure},
             {"divergence_unconverged", f.unconvergedDivergence}};
  const DfsphSettings& d = settings_;
  if (f.unconvergedPressure > 0) {
    const std::string capped =
        cappedDensityTolerance_
            ? fmt::format(", {:.3g} % in the steps below the depth cap", 100 * *cappedDensityTolerance_)
            : "";
    r.warnings.push_back(fmt::format(
        "{} of {} constant-density solves stopped at solver.dfsph.max_iterations ({}) above "
        "solver.dfsph.max_density_error ({:.3g} %{}): mean density error up to {:.3g} %, so the particles "
        "end the step compressed; a smaller time.dt_max (or more iterations) lets the solve converge",
        f.unconvergedPressure, f.solves, d.maxIterations, 100 * d.maxDensityError, capped,
        100 * f.maxDensityError));
  }
  if (f.unconvergedDivergence > 0)
    r.warnings.push_back(fmt::format(
        "{} of {} divergence solves stopped at solver.dfsph.max_iterations ({}) above "
        "solver.dfsph.max_divergence_error ({:.3g} %): error up to {:.3g} %; a smaller time.dt_max (or "
        "more iterations) lets the solve converge",
        f.unconvergedDivergence, f.solves, d.maxIterations, 100 * d.maxDivergenceError,
        100 * f.maxDivergenceError));
  return r;
}

}  // namespace sphfx::sim
