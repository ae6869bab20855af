#include "simulator.h"

#include <fmt/format.h>

#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "bindings.h"
#include "sim_shaders.h"
#include "sphfx/core/error.h"
#include "sphfx/core/log.h"
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
      return std::make_unique<DFSPHSolver>(scene, gate, defines, uint32_t(maxParticleCount(scene)),
                                           boundary.gateEntry(), boundary.count());
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
  dynamic_ = scene.changesParticleCount();
  // A varying count: the buffers are sized once for the most particles the scene can hold.
  capacity_ = dynamic_ ? uint32_t(maxParticleCount(scene)) : count_;
  if (capacity_ == 0) throw InputError("fluid.blocks: the blocks hold no particles at this spacing");
  defines_ = simShaderDefines(scene);
  if (workgroupReduce()) defines_.set("SIM_WORKGROUP_REDUCE");
  if (visitEverySample()) defines_.set("SIM_VISIT_EVERY_SAMPLE");
  gate_ = std::make_unique<DispatchGate>(capacity_);
  const GridSpec spec = GridSpec::forScene(scene);
  warnIfWallLatticeMisfits(scene);
  if (const std::optional<double> tolerance = dfsphCappedDensityTolerance(scene)) {
    const double cap = stepCap(scene);
    logInfo(
        fmt::format("DFSPH: the steps that {} sets, {:.3g} ms, below the depth cap's {:.3g} ms, solve the "
                    "density to {:.3g} (max_density_error x their ratio squared)",
                    cap < scene.time.dtMax ? "the artificial viscosity's bound" : "time.dt_max", 1e3 * cap,
                    1e3 * scene.dfsphDepthStep(), *tolerance));
  }
  grid_ = std::make_unique<NeighborGrid>(*gate_, spec, capacity_, dynamic_);
  boundary_ = std::make_unique<BoundaryAkinci2012>(
      wallSamplingScene(scene, boundaryLayers(scene) * scene.fluid.spacing),
      buildColliderFields(scene, shotDir), *gate_, spec, defines_);
  solver_ = makePressureSolver(scene, *gate_, defines_, *boundary_);
  stepper_ = std::make_unique<SymplecticEuler>(*gate_, defines_);
  health_ = ShaderProgram::compute(simShaderTable(), "sim_health.comp", defines_);

  const SimParams params = makeSimParams(scene, capacity_, boundary_->count(), gate_->entries());
  params_.resize(sizeof params);
  params_.upload(&params, sizeof params);
  state_.resize(sizeof(SimState));
  posIn_ = vec4Buffer(capacity_);
  velIn_ = vec4Buffer(capacity_);
  pos_ = vec4Buffer(capacity_);
  vel_ = vec4Buffer(capacity_);
  accel_ = vec4Buffer(capacity_);
  density_ = GpuBuffer(size_t(capacity_) * 8);
  if (dynamic_) setUpDynamic();

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
  if (dynamic_ ? (s.position.size() > capacity_ || s.velocity.size() != s.position.size())
               : (s.position.size() != count_ || s.velocity.size() != count_))
    throw InputError(fmt::format("restart state has {} particles, the scene {} {}", s.position.size(),
                                 dynamic_ ? "holds at most" : "has", dynamic_ ? capacity_ : count_));
  frame_ = s.frame;
  if (dynamic_) {
    count_ = uint32_t(s.position.size());
    std::vector<uint32_t> head(2 + std::max<size_t>(scene_.emitters.size(), 1), 0u);
    head[0] = count_;
    dynamicState_.upload(head.data(), head.size() * 4);
  }
  posIn_.upload(s.position.data(), size_t(count_) * 16);
  velIn_.upload(s.velocity.data(), size_t(count_) * 16);
  // Density and pressure of the restored positions (cache attributes, health) and the static boundary
  // sort: one gated substep without time step or integration.
  const double t = scene_.frameTime(frame_);
  startFrame(t, t);
  timer_.begin("boundary");
  params_.bindUniform(SPHFX_UBO_SIM_PARAMS);
  state_.bindStorage(SPHFX_SSBO_SIM_STATE);
  if (dynamic_) {
    bindDynamic();
    syncEmitters();  // the emitters' layer counts and the next id at this frame's time
  }
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
  if (dynamic_) bindDynamic();
}

void Simulator::substep() {
  params_.bindUniform(SPHFX_UBO_SIM_PARAMS);
  state_.bindStorage(SPHFX_SSBO_SIM_STATE);
  if (dynamic_) bindDynamic();
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
  if (!scene_.emitters.empty()) {
    timer_.begin("emit");
    emit();
  }
  timer_.end();
}

void Simulator::setUpDynamic() {
  // [live, next id, layers emitted per emitter] (sph_dynamic.glsl); restoreState() fills it.
  dynamicState_ = GpuBuffer((2 + std::max<size_t>(scene_.emitters.size(), 1)) * 4);
  if (!scene_.kill.empty()) {
    std::vector<std::array<float, 4>> boxes;
    for (const KillBox& k : scene_.kill) {
      boxes.push_back({float(k.min[0]), float(k.min[1]), float(k.min[2]), 0.0f});
      boxes.push_back({float(k.max[0]), float(k.max[1]), float(k.max[2]), 0.0f});
    }
    killBoxes_ = GpuBuffer(boxes.size() * 16);
    killBoxes_.uploadVector(boxes);
  }
  if (scene_.emitters.empty()) return;
  std::vector<EmitterGpu> table;
  std::vector<std::array<float, 4>> points;
  for (size_t e = 0; e < scene_.emitters.size(); ++e) {
    const Emitter& em = scene_.emitters[e];
    const std::vector<Vec3d> layer = emitterLayerPoints(scene_, em);
    const double len = std::sqrt(em.direction[0] * em.direction[0] + em.direction[1] * em.direction[1] +
                                 em.direction[2] * em.direction[2]);
    EmitterGpu g{};
    g.time[0] = em.start;
    g.time[1] = scene_.fluid.spacing / em.speed;
    for (int a = 0; a < 3; ++a) g.dirSpeed[a] = float(em.direction[a] / len);
    g.dirSpeed[3] = float(em.speed);
    g.info[0] = uint32_t(layer.size());
    g.info[1] = uint32_t(points.size());
    g.info[2] = uint32_t(emitterLayers(scene_, em));
    g.info[3] = em.shape == EmitterShape::Disc ? 0u : 1u;  // a volume source: only its newest due layer
    for (int a = 0; a < 3; ++a) {
      g.regionA[a] = float(em.shape == EmitterShape::Box ? em.min[a] : em.center[a]);
      g.regionB[a] = float(em.max[a]);
    }
    g.regionA[3] = float(em.radius);
    g.regionB[3] = em.shape == EmitterShape::Box ? 1.0f : em.shape == EmitterShape::Sphere ? 2.0f : 0.0f;
    table.push_back(g);
    for (const Vec3d& p : layer)
      points.push_back({float(p[0]), float(p[1]), float(p[2]), std::bit_cast<float>(uint32_t(e))});
  }
  emitterPointCount_ = uint32_t(points.size());
  emitters_ = GpuBuffer(table.size() * sizeof(EmitterGpu));
  emitters_.upload(table.data(), table.size() * sizeof(EmitterGpu));
  emitterPoints_ = GpuBuffer(points.size() * 16);
  emitterPoints_.uploadVector(points);
  emit_ = ShaderProgram::compute(simShaderTable(), "sim_emit.comp", defines_);
  emitCommit_ = ShaderProgram::compute(simShaderTable(), "sim_emit_commit.comp", defines_);
  glProgramUniform1ui(emit_.id(), emit_.uniform("uPoints"), emitterPointCount_);
  glProgramUniform1ui(emitCommit_.id(), emitCommit_.uniform("uEmitters"), uint32_t(table.size()));
  glProgramUniform1ui(emitCommit_.id(), emitCommit_.uniform("uInitialParticles"),
                      uint32_t(countInitialParticles(scene_)));
}

void Simulator::bindDynamic() const {
  dynamicState_.bindStorage(SPHFX_SSBO_SIM_DYNAMIC);
  if (!scene_.emitters.empty()) {
    emitters_.bindStorage(SPHFX_SSBO_SIM_EMITTERS);
    emitterPoints_.bindStorage(SPHFX_SSBO_SIM_EMITTER_POINTS);
  }
  if (!scene_.kill.empty()) killBoxes_.bindStorage(SPHFX_SSBO_SIM_KILL_BOXES);
}

// The due layers after the live particles, then the counts (sim_emit.comp, sim_emit_commit.comp). Not
// gated: once the frame is reached no layer is due, so a queued substep past it emits nothing.
void Simulator::emit() const {
  emit_.use();
  dispatchCompute1D(emit_, emitterPointCount_, "sim_emit.comp");
  storageBarrier();
  emitCommit_.use();
  glProgramUniform1ui(emitCommit_.id(), emitCommit_.uniform("uSync"), 0u);
  glDispatchCompute(1, 1, 1);
  glCheck("sim_emit_commit.comp");
  storageBarrier();
}

void Simulator::syncEmitters() const {
  if (scene_.emitters.empty()) return;
  emitCommit_.use();
  glProgramUniform1ui(emitCommit_.id(), emitCommit_.uniform("uSync"), 1u);
  glDispatchCompute(1, 1, 1);
  glCheck("sim_emit_commit.comp");
  storageBarrier();
}

// The frame's end state without its removed particles: a grid build compacts the live ones into the
// sorted copies, which become the state (the next substep's sort of an already sorted state gives the
// order it would have given anyway: the sort is stable), and the live count is read back.
void Simulator::compact() {
  gate_->arm();
  params_.bindUniform(SPHFX_UBO_SIM_PARAMS);
  state_.bindStorage(SPHFX_SSBO_SIM_STATE);
  bindDynamic();
  timer_.begin("compact");
  grid_->build(posIn_, velIn_, pos_, vel_);
  timer_.end();
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  uint32_t live = 0;
  dynamicState_.download(&live, 4);
  count_ = live;
  glCopyNamedBufferSubData(pos_.id(), posIn_.id(), 0, 0, GLsizeiptr(capacity_) * 16);
  glCopyNamedBufferSubData(vel_.id(), velIn_.id(), 0, 0, GLsizeiptr(capacity_) * 16);
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
  if (dynamic_) compact();
  timer_.begin("health");
  bindSolverBuffers();
  health_.use();
  dispatchCompute1D(health_, capacity_, "sim_health.comp");
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
  SolverFrameReport report = solver_->frameReport();
  f.solverStats = std::move(report.stats);
  if (dfsphWarmsFlowLimited(scene_)) f.solverStats.emplace_back("pressure_warm_substeps", s.warmSubsteps);
  f.warnings = std::move(report.warnings);
  if (dynamic_) f.particles = int64_t(count_);
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
      add(fmt::format("speed {:.4g} m/s above health.max_speed {:.4g}{}", std::sqrt(v2),
                      scene_.health.maxSpeed, whereFastest()));
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

// Where a particle is: its position and the nearest wall of the domain.
std::string Simulator::placeOf(const std::array<float, 4>& x) const {
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

// Where the densest particle of the failed substep is (the stops measured so far compressed against a
// wall, docs/validation.md "Known limits"). Read back only on failure; the density and sorted positions
// are those of the substep that failed (its later passes did not run).
std::string Simulator::whereDensest() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  if (count_ == 0) return "";
  const auto rho = density_.downloadVector<std::array<float, 2>>(count_);
  const auto pos = pos_.downloadVector<std::array<float, 4>>(count_);
  uint32_t densest = 0;
  for (uint32_t i = 1; i < count_; ++i)
    // A NaN density is never chosen (the non-finite check reports it), nor kept if particle 0 has one.
    if (std::isfinite(rho[i][0]) && !(rho[i][0] <= rho[densest][0])) densest = i;
  return placeOf(pos[densest]);
}

// Where the fastest particle of the failed substep is, with its own speed: the velocities as the failed
// substep left them (its integration did not run), beside the sorted positions.
std::string Simulator::whereFastest() const {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  if (count_ == 0) return "";
  const auto vel = vel_.downloadVector<std::array<float, 4>>(count_);
  const auto pos = pos_.downloadVector<std::array<float, 4>>(count_);
  auto speed2 = [&](uint32_t i) {
    return vel[i][0] * vel[i][0] + vel[i][1] * vel[i][1] + vel[i][2] * vel[i][2];
  };
  uint32_t fastest = 0;
  for (uint32_t i = 1; i < count_; ++i)
    if (std::isfinite(speed2(i)) && !(speed2(i) <= speed2(fastest))) fastest = i;
  return fmt::format(" (fastest particle {:.4g} m/s{})", std::sqrt(speed2(fastest)), placeOf(pos[fastest]));
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
  if (dynamic_) bindDynamic();
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
  // A count that changes needs ids to follow a particle from frame to frame: cached always then.
  if (scene_.hasCacheAttribute(CacheAttribute::Id) || dynamic_)
    for (const auto& p : s.position) f.id.push_back(std::bit_cast<int32_t>(p[3]));
  return f;
}

}  // namespace sphfx::sim
