#include "simulator.h"

#include <fmt/format.h>

#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>

#include "bindings.h"
#include "sim_shaders.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"

namespace sphfx::sim {

std::unique_ptr<PressureSolver> makePressureSolver(const Scene& scene, const DispatchGate& gate,
                                                   const ShaderDefines& defines,
                                                   const BoundaryAkinci2012& boundary) {
  switch (scene.solver.method) {  // one case per entry of pressureSolverRegistry()
    case Solver::WCSPH:
      return std::make_unique<WCSPHSolver>(scene, gate, defines, boundary.gateEntry(), boundary.count());
    case Solver::DFSPH:
      return std::make_unique<DFSPHSolver>(scene, gate, defines, uint32_t(countInitialParticles(scene)));
  }
  throw InputError("solver.method: no implementation of \"" +
                   methodEntry(pressureSolverRegistry(), scene.solver.method).name + "\" in this build");
}

namespace {
GpuBuffer vec4Buffer(uint32_t count) {
  return GpuBuffer(std::max<size_t>(count, 1) * 16);
}
}  // namespace

Simulator::Simulator(const Scene& scene, const std::string& shotDir)
    : scene_(scene), frame_(scene.time.startFrame) {
  const SeededParticles seeds = seedParticles(scene);
  count_ = uint32_t(seeds.position.size());
  if (count_ == 0) throw InputError("fluid.blocks: the blocks hold no particles at this spacing");
  defines_ = simShaderDefines(scene);
  gate_ = std::make_unique<DispatchGate>(count_);
  const GridSpec spec = GridSpec::forScene(scene);
  grid_ = std::make_unique<NeighborGrid>(*gate_, spec, count_);
  boundary_ = std::make_unique<BoundaryAkinci2012>(scene, buildColliderFields(scene, shotDir), *gate_,
                                                   spec, defines_);
  solver_ = makePressureSolver(scene, *gate_, defines_, *boundary_);
  stepper_ = std::make_unique<SymplecticEuler>(*gate_, defines_);
  health_ = ShaderProgram::compute(simShaderTable(), "sim_health.comp", defines_);

  const SimParams params = makeSimParams(scene, count_, boundary_->count(), gate_->entries());
  params_.resize(sizeof params);
  params_.upload(&params, sizeof params);
  state_.resize(sizeof(SimState));
  posIn_ = vec4Buffer(count_);
  velIn_ = vec4Buffer(count_);
  pos_ = vec4Buffer(count_);
  vel_ = vec4Buffer(count_);
  accel_ = vec4Buffer(count_);
  density_ = GpuBuffer(size_t(count_) * 8);

  SimulatorState initial;
  initial.frame = frame_;
  for (uint32_t i = 0; i < count_; ++i) {
    const auto& p = seeds.position[i];
    const auto& v = seeds.velocity[i];
    initial.position.push_back({p[0], p[1], p[2], std::bit_cast<float>(i)});
    initial.velocity.push_back({v[0], v[1], v[2], 0.0f});
  }
  restoreState(initial);
}

void Simulator::restoreState(const SimulatorState& s) {
  if (s.position.size() != count_ || s.velocity.size() != count_)
    throw InputError(
        fmt::format("restart state has {} particles, the scene has {}", s.position.size(), count_));
  frame_ = s.frame;
  posIn_.upload(s.position.data(), size_t(count_) * 16);
  velIn_.upload(s.velocity.data(), size_t(count_) * 16);
  // Density and pressure of the restored positions (cache attributes, health) and the static boundary
  // sort: one gated substep without time step or integration.
  const double t = scene_.frameTime(frame_);
  startFrame(t, t);
  timer_.begin("boundary");
  params_.bindUniform(SPHFX_UBO_SIM_PARAMS);
  state_.bindStorage(SPHFX_SSBO_SIM_STATE);
  boundary_->prepare();
  timer_.begin("grid");
  grid_->build(posIn_, velIn_, pos_, vel_);
  bindSolverBuffers();
  solver_->computeDensity(timer_);
  timer_.end();
  // The density pass worked on the sorted copies; the state between steps is the unsorted order, so
  // keep the sorted order as the new state (the permutation is deterministic).
  glCopyNamedBufferSubData(pos_.id(), posIn_.id(), 0, 0, GLsizeiptr(count_) * 16);
  glCopyNamedBufferSubData(vel_.id(), velIn_.id(), 0, 0, GLsizeiptr(count_) * 16);
}

void Simulator::startFrame(double t0, double t1) {
  SimState s{};
  s.time = t0;
  s.frameEnd = t1;
  s.dtLow = std::numeric_limits<float>::max();
  for (int k = 0; k < 4; ++k) s.healthFirst[k] = 0xffffffffu;
  state_.upload(&s, sizeof s);
  gate_->arm();
}

void Simulator::bindSolverBuffers() const {
  params_.bindUniform(SPHFX_UBO_SIM_PARAMS);
  state_.bindStorage(SPHFX_SSBO_SIM_STATE);
  posIn_.bindStorage(SPHFX_SSBO_SIM_UNSORTED_POS);
  velIn_.bindStorage(SPHFX_SSBO_SIM_UNSORTED_VEL);
  pos_.bindStorage(SPHFX_SSBO_SIM_POS);
  vel_.bindStorage(SPHFX_SSBO_SIM_VEL);
  density_.bindStorage(SPHFX_SSBO_SIM_DENSITY);
  accel_.bindStorage(SPHFX_SSBO_SIM_ACCEL);
  grid_->rowStart().bindStorage(SPHFX_SSBO_SIM_CELL_START);
  pos_.bindTexture(SPHFX_TEX_SIM_POS, GL_RGBA32F);
  vel_.bindTexture(SPHFX_TEX_SIM_VEL, GL_RGBA32F);
  density_.bindTexture(SPHFX_TEX_SIM_DENSITY, GL_RG32F);
  grid_->rowStart().bindTexture(SPHFX_TEX_SIM_CELL_START, GL_R32UI);
  boundary_->bind();
}

void Simulator::substep() {
  params_.bindUniform(SPHFX_UBO_SIM_PARAMS);
  state_.bindStorage(SPHFX_SSBO_SIM_STATE);
  timer_.begin("boundary");
  boundary_->update();
  timer_.begin("grid");
  grid_->build(posIn_, velIn_, pos_, vel_);
  bindSolverBuffers();
  solver_->computeAccelerations(timer_);
  stepper_->chooseStep(timer_);
  bindSolverBuffers();  // the time step pass bound the dispatch arguments over a storage point
  solver_->correctVelocities(timer_);
  bindSolverBuffers();
  stepper_->integrate(timer_);
  timer_.end();
}

SimState Simulator::readState() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  SimState s{};
  state_.download(&s, sizeof s);
  return s;
}

FrameStats Simulator::advance() {
  const auto wall0 = std::chrono::steady_clock::now();
  const int next = frame_ + 1;
  startFrame(scene_.frameTime(frame_), scene_.frameTime(next));
  // Queue substeps in batches sized from the previous frame; the GPU closes the dispatches once the
  // frame time is reached, so over-queuing costs only empty dispatches. One read-back per batch.
  int batch = std::max(1, lastSubsteps_);
  SimState s{};
  for (;;) {
    for (int k = 0; k < batch; ++k) substep();
    s = readState();
    if (s.done) break;
    const double remaining = s.frameEnd - s.time;
    batch = int(std::clamp(std::ceil(remaining / std::max<double>(s.dt, 1e-12)), 1.0, 256.0));
  }
  timer_.begin("health");
  bindSolverBuffers();
  health_.use();
  dispatchCompute1D(health_, count_, "sim_health.comp");
  timer_.end();
  s = readState();
  timer_.collect();
  frame_ = next;
  checkHealth(s);
  if (cachesDensity()) refreshFrameDensity();
  lastSubsteps_ = int(s.substeps);
  FrameStats f;
  f.frame = next;
  f.substeps = int(s.substeps);
  f.dtMin = s.dtLow;
  f.dtMax = s.dtHigh;
  f.dtMean = s.substeps ? s.dtSum / s.substeps : 0;
  f.solverStats = solver_->frameStats();
  f.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return f;
}

void Simulator::checkHealth(const SimState& s) const {
  if (s.failure) {
    std::string causes;
    auto add = [&](const std::string& c) { causes += (causes.empty() ? "" : "; ") + c; };
    const float v2 = std::bit_cast<float>(s.maxSpeed2), rho = std::bit_cast<float>(s.maxDensity);
    if (s.failure & kFailNonFinite) add("non-finite velocity, acceleration or density (NaN/Inf)");
    if (s.failure & kFailSpeed)
      add(fmt::format("speed {:.4g} m/s above health.max_speed {:.4g}", std::sqrt(v2),
                      scene_.health.maxSpeed));
    if (s.failure & kFailDensity)
      add(fmt::format("density {:.5g} kg/m^3 above health.max_density_ratio {} x rest density{}", rho,
                      scene_.health.maxDensityRatio, whereDensest()));
    if (s.failure & kFailDt) add(fmt::format("CFL time step below time.dt_min {:.3g} s", scene_.time.dtMin));
    if (s.failure & kFailNeighbors)
      add(
          fmt::format("a particle has more than {} fluid neighbours within the kernel support (packed far "
                      "denser than fluid.packing {}: the DFSPH neighbour list is full)",
                      DFSPHSolver::listSlots(scene_), scene_.fluid.packing));
    throw SimulationError(fmt::format("frame {}, substep {}: {}", frame_, s.failSubstep, causes));
  }
  static const char* what[4] = {"with non-finite position, velocity or density", "outside the domain",
                                "faster than health.max_speed", "denser than health.max_density_ratio"};
  for (int k = 0; k < 4; ++k)
    if (s.healthCount[k])
      throw SimulationError(fmt::format("frame {}, substep {} (end of frame): {} particles {} (first id {})",
                                        frame_, s.substeps, s.healthCount[k], what[k], s.healthFirst[k]));
}

// Where the densest particle of the failed substep is: its position and the nearest wall of the domain
// (the stops measured so far compressed against a wall, docs/validation.md "Known limits"). Read back only on
// failure; the density and sorted positions are those of the substep that failed (its later passes did not
// run).
std::string Simulator::whereDensest() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const auto rho = density_.downloadVector<std::array<float, 2>>(count_);
  const auto pos = pos_.downloadVector<std::array<float, 4>>(count_);
  uint32_t densest = 0;
  for (uint32_t i = 1; i < count_; ++i)
    // A NaN density is never chosen (the non-finite check reports it), nor kept if particle 0 has one.
    if (std::isfinite(rho[i][0]) && !(rho[i][0] <= rho[densest][0])) densest = i;
  const auto& x = pos[densest];
  static const char* face[3][2] = {{"x-min", "x-max"}, {"y-min", "y-max"}, {"z-min", "z-max"}};
  double nearest = std::numeric_limits<double>::infinity();
  const char* name = nullptr;
  for (int a = 0; a < 3; ++a) {
    if (scene_.domain.isPeriodic(a)) continue;
    const double d[2] = {x[a] - scene_.domain.min[a], scene_.domain.max[a] - x[a]};
    for (int side = 0; side < 2; ++side)
      if (d[side] < nearest) {
        nearest = d[side];
        name = face[a][side];
      }
  }
  std::string where = fmt::format(" at ({:.4f}, {:.4f}, {:.4f}) m", x[0], x[1], x[2]);
  if (name)
    where += fmt::format(", {:.2f} spacings from the domain's {} wall", nearest / scene_.fluid.spacing, name);
  return where;
}

SimulatorState Simulator::downloadState(const GpuBuffer& position, const GpuBuffer& velocity) const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  SimulatorState s;
  s.frame = frame_;
  s.position.resize(count_);
  s.velocity.resize(count_);
  position.download(s.position.data(), size_t(count_) * 16);
  velocity.download(s.velocity.data(), size_t(count_) * 16);
  return s;
}

SimulatorState Simulator::saveState() const {
  return downloadState(posIn_, velIn_);
}

bool Simulator::cachesDensity() const {
  return scene_.hasCacheAttribute(CacheAttribute::Density) ||
         scene_.hasCacheAttribute(CacheAttribute::Pressure);
}

// Sorts the frame's final state into the sorted copies (the state itself stays as it is, so the next
// substep and a restart see exactly what they would without this pass) and computes their density and
// pressure at the frame's time: cacheFrame() then reads positions and attributes of one instant.
void Simulator::refreshFrameDensity() {
  const double t = scene_.frameTime(frame_);
  startFrame(t, t);
  timer_.begin("frame_density");
  params_.bindUniform(SPHFX_UBO_SIM_PARAMS);
  state_.bindStorage(SPHFX_SSBO_SIM_STATE);
  boundary_->update();
  grid_->build(posIn_, velIn_, pos_, vel_);
  bindSolverBuffers();
  solver_->computeDensity(timer_);
  timer_.end();
}

ParticleFrame Simulator::cacheFrame() const {
  // With cached density the sorted copies hold the frame's state in the attributes' order.
  const SimulatorState s = cachesDensity() ? downloadState(pos_, vel_) : saveState();
  ParticleFrame f;
  f.frame = frame_;
  f.time = scene_.frameTime(frame_);
  f.particleSpacing = scene_.fluid.spacing;
  f.position.resize(count_);
  f.velocity.resize(count_);
  for (uint32_t i = 0; i < count_; ++i) {
    f.position[i] = {s.position[i][0], s.position[i][1], s.position[i][2]};
    f.velocity[i] = {s.velocity[i][0], s.velocity[i][1], s.velocity[i][2]};
  }
  const bool wantDensity = scene_.hasCacheAttribute(CacheAttribute::Density);
  const bool wantPressure = scene_.hasCacheAttribute(CacheAttribute::Pressure);
  if (wantDensity || wantPressure) {
    const auto dp = density_.downloadVector<std::array<float, 2>>(count_);
    for (const auto& v : dp) {
      if (wantDensity) f.density.push_back(v[0]);
      if (wantPressure) f.pressure.push_back(v[1] * v[0] * v[0]);  // stored as p / rho^2
    }
  }
  if (scene_.hasCacheAttribute(CacheAttribute::Id))
    for (const auto& p : s.position) f.id.push_back(std::bit_cast<int32_t>(p[3]));
  return f;
}

}  // namespace sphfx::sim
