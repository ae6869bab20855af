#pragma once
// Shared helpers of the simulation tests: a GL context per the SPHFX_GL backend, small scenes, the GPU
// neighbour search, total momentum.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "../common/scratch_dir.h"
#include "bindings.h"
#include "dispatch_gate.h"
#include "gpu_types.h"
#include "neighbor_grid.h"
#include "sim_shaders.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/shader_program.h"
#include "sphfx/sim/simulation.h"

namespace sphfx::test {

// Sets an environment variable for its lifetime, restoring the previous value (or its absence).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (old_)
      setenv(name_, old_->c_str(), 1);
    else
      unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

inline std::unique_ptr<GLContext> makeContext() {
  const char* name = std::getenv("SPHFX_GL");
  return GLContext::create({parseGLBackend(name ? name : "auto"), false});
}

/// A test run for each solver name its instantiation lists ("wcsph", "dfsph"), on a GL context; derive a
/// suite from it and instantiate with solverParamName() for readable test names.
class SolverTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { ctx_ = makeContext(); }
  std::unique_ptr<GLContext> ctx_;
};

inline std::string solverParamName(const ::testing::TestParamInfo<std::string>& info) {
  return info.param;
}

/// Simulates `scene` into the shot sim_test_NAME in the process's scratch folder (scratch_dir.h; emptied
/// first unless `resume`), without a progress line; returns the shot folder.
inline std::string simulateTestShot(const std::string& name, const Scene& scene, bool resume = false) {
  const std::string shot = scratchPath("sim_test_" + name).string();
  if (!resume) std::filesystem::remove_all(shot);
  sim::SimulationOptions o;
  o.shotDir = shot;
  o.resume = resume;
  o.progress = false;
  sim::simulateShot(scene, o);
  return shot;
}

/// A scene from JSON text with the given overrides.
inline Scene sceneFromJson(const std::string& text) {
  return parseScene(schema::Json::parse(text), "test");
}

/// The (T, Z) rows of a front table shipped in studies/reference (Martin & Moyce's, sources in its header).
inline std::vector<std::pair<double, double>> readFrontTable(const std::string& file) {
  std::ifstream in(std::string(SPHFX_SOURCE_DIR) + "/studies/reference/" + file);
  std::vector<std::pair<double, double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'T') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream row(line);
    double t, z;
    if (row >> t >> z) rows.push_back({t, z});
  }
  return rows;
}

/// Sum of the particles' velocities (momentum / particle mass).
/// scenes/hydrostatic.json with a square pillar, a box collider from below the floor (y = -0.05 m) to above
/// the 0.3 m surface, and the fluid in four blocks around it; `more` overrides are applied after these.
inline Scene pillarTank(std::vector<std::string> more) {
  std::vector<std::string> o{R"(colliders=[{"shape":"box","min":[0.06,-0.05,0.06],"max":[0.14,0.35,0.14]}])",
                             R"(fluid.blocks=[{"shape":"box","min":[0,0,0],"max":[0.06,0.3,0.2]},)"
                             R"({"shape":"box","min":[0.14,0,0],"max":[0.2,0.3,0.2]},)"
                             R"({"shape":"box","min":[0.06,0,0],"max":[0.14,0.3,0.06]},)"
                             R"({"shape":"box","min":[0.06,0,0.14],"max":[0.14,0.3,0.2]}])"};
  o.insert(o.end(), more.begin(), more.end());
  return loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/hydrostatic.json", o);
}

inline std::array<double, 3> momentum(const ParticleFrame& f) {
  std::array<double, 3> m{};
  for (const auto& v : f.velocity)
    for (int a = 0; a < 3; ++a) m[a] += v[a];
  return m;
}

/// Items within h of each item through the GPU grid and sim_grid_neighbors.comp compiled with the scene's
/// shader defines (the same sphRow/sphRowWrap/sphDelta as the solver passes). Per sorted slot: ids.
inline std::vector<std::pair<uint32_t, std::set<uint32_t>>> gpuNeighbours(
    const Scene& scene, const std::vector<std::array<float, 4>>& items) {
  const uint32_t n = uint32_t(items.size()), maxN = 400;
  sim::DispatchGate gate(n);
  sim::NeighborGrid grid(gate, sim::GridSpec::forScene(scene), n);
  gate.arm();
  GpuBuffer pos(n * 16), vel(n * 16), sorted(n * 16), sortedVel(n * 16), out(size_t(n) * (maxN + 1) * 4);
  pos.uploadVector(items);
  vel.uploadVector(items);
  grid.build(pos, vel, sorted, sortedVel);
  const sim::SimParams params = sim::makeSimParams(scene, n, 0, gate.entries());
  GpuBuffer ubo(sizeof params);
  ubo.upload(&params, sizeof params);
  ubo.bindUniform(SPHFX_UBO_SIM_PARAMS);
  sorted.bindStorage(SPHFX_SSBO_SIM_POS);
  grid.rowStart().bindStorage(SPHFX_SSBO_SIM_CELL_START);
  out.bindStorage(SPHFX_SSBO_SIM_GRID_NEIGHBORS);
  ShaderProgram program =
      ShaderProgram::compute(simShaderTable(), "sim_grid_neighbors.comp", sim::simShaderDefines(scene));
  program.use();
  glUniform1ui(program.uniform("uMaxNeighbors"), maxN);
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  dispatchCompute1D(program, n, "neighbors");
  glMemoryBarrier(GL_ALL_BARRIER_BITS);
  const auto got = out.downloadVector<uint32_t>(size_t(n) * (maxN + 1));
  const auto sortedItems = sorted.downloadVector<std::array<float, 4>>(n);
  std::vector<std::pair<uint32_t, std::set<uint32_t>>> result;
  for (uint32_t s = 0; s < n; ++s) {
    const uint32_t count = got[size_t(s) * (maxN + 1)];
    EXPECT_LE(count, maxN);
    const auto begin = got.begin() + long(s) * (maxN + 1) + 1;
    const std::set<uint32_t> found(begin, begin + std::min(count, maxN));
    EXPECT_EQ(found.size(), count) << "duplicate neighbours (a cell visited twice across the seam)";
    result.emplace_back(std::bit_cast<uint32_t>(sortedItems[s][3]), found);
  }
  return result;
}

}  // namespace sphfx::test
