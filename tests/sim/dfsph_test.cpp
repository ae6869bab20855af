// DFSPH (Bender & Koschier 2015/2017) on the GPU: hydrostatic rest state and pressure, the solver's own
// error reports, a large-time-step dam break against Martin & Moyce, divergence-free velocities,
// determinism and bit-identical resume, moving colliders. Small resolutions: llvmpipe in CI.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "sphfx/core/gl_context.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/core/scene.h"
#include "sphfx/sim/simulation.h"
#include "sphfx/sim/simulator.h"
#include "sphfx/study/metrics.h"
#include "sphfx/study/references.h"

namespace sphfx::sim {
namespace {

namespace fs = std::filesystem;

Scene scene(const std::string& file, std::vector<std::string> overrides) {
  overrides.insert(overrides.begin(), "solver.method=dfsph");
  return loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/" + file, overrides);
}

double stat(const FrameStats& f, const std::string& key) {
  for (const auto& [k, v] : f.solverStats)
    if (k == key) return v;
  ADD_FAILURE() << "no solver statistic " << key;
  return 0;
}

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sphfx_dfsph_" + name);
  fs::remove_all(dir);
  return dir;
}

class DFSPH : public ::testing::Test {
 protected:
  void SetUp() override { ctx_ = GLContext::create(); }
  std::unique_ptr<GLContext> ctx_;
};

// A tank at rest: densities at rest density (walls included), pressure rho0 g (H - y), each step's
// constant-density solve within the scene's tolerance, velocities near zero (no drift, no sticking).
TEST_F(DFSPH, HydrostaticTankReachesRestDensityAndPressureProfile) {
  const Scene s = scene("hydrostatic.json", {"fluid.spacing=0.02", "time.end_frame=25", "time.dt_max=0.01"});
  Simulator sim(s);
  FrameStats last;
  while (sim.frame() < s.time.endFrame) {
    last = sim.advance();
    EXPECT_LE(stat(last, "density_error_max"), s.solver.maxDensityError) << "frame " << last.frame;
    EXPECT_GE(stat(last, "pressure_iterations_mean"), s.solver.minIterations);
  }
  const ParticleFrame f = sim.cacheFrame();
  const double height = 0.3;  // the block's top: volume is conserved
  const study::HydrostaticError e =
      study::hydrostaticError(f, s.fluid.restDensity, -s.gravity[1], height, s.kernelRadius());
  // Free-surface particles lack neighbours and sit below rest density, so the mean is taken inside.
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < f.position.size(); ++i)
    if (f.position[i][1] < height - s.kernelRadius()) {
      sum += f.density[i];
      ++n;
    }
  const double interior = sum / n / s.fluid.restDensity - 1;
  EXPECT_LT(std::abs(interior), 0.01) << "interior mean density error";
  EXPECT_LT(e.pressureL2, 0.15) << "pressure profile vs rho0 g (H - y)";
  double vmax = 0;
  for (const auto& v : f.velocity) vmax = std::max(vmax, double(std::hypot(v[0], v[1], v[2])));
  EXPECT_LT(vmax, 0.05) << "the tank should be at rest";
}

// The divergence solve leaves an average compression rate below its tolerance, and warm starting keeps
// the iteration counts low once the flow has settled.
TEST_F(DFSPH, DivergenceSolveMeetsItsTolerance) {
  const Scene s = scene("hydrostatic.json", {"fluid.spacing=0.02", "time.end_frame=10", "time.dt_max=0.01",
                                             "solver.max_divergence_error=0.1"});
  Simulator sim(s);
  while (sim.frame() < s.time.endFrame) {
    const FrameStats f = sim.advance();
    EXPECT_LE(stat(f, "divergence_error_max"), s.solver.maxDivergenceError) << "frame " << f.frame;
    EXPECT_LT(stat(f, "divergence_iterations_max"), s.solver.maxIterations) << "frame " << f.frame;
  }
}

// Dam break (a = 0.2, n^2 = 2) at frame-sized steps: dt reaches 0.014 s or more, the run stays healthy
// and the surge front follows Martin & Moyce.
TEST_F(DFSPH, DamBreakAtLargeTimeStepMatchesMartinMoyce) {
  const Scene s = scene("dam_break.json", {"fluid.spacing=0.02", "time.end_frame=13", "time.dt_max=0.02",
                                           "time.cfl_factor=1.5"});
  const auto ref = study::MartinMoyce::load(study::referenceDirectory());
  Simulator sim(s);
  const double a = 0.2, g = 9.81;
  std::vector<study::CurveSample> front;
  double dtMax = 0;
  while (sim.frame() < s.time.endFrame) {
    const FrameStats f = sim.advance();
    dtMax = std::max(dtMax, f.dtMax);
    EXPECT_LE(stat(f, "density_error_mean"), 2 * s.solver.maxDensityError) << "frame " << f.frame;
    const double t = s.frameTime(sim.frame());
    front.push_back({t * std::sqrt(2 * g / a), study::surgeFront(sim.cacheFrame(), 0.0) / a});
  }
  EXPECT_GE(dtMax, 0.014);
  const study::CurveError e = study::relativeError(front, ref.front, 3.0);
  EXPECT_GE(e.samples, 5u);
  EXPECT_LT(e.rms, 0.15) << "surge front vs Martin & Moyce (relative RMS)";
}

// Same scene twice: byte-identical caches (deterministic reductions, no float atomics). Then a run
// resumed from a restart file continues bit-identically (the warm start travels in the state).
TEST_F(DFSPH, CachesAreDeterministicAndResumeIsBitIdentical) {
  const Scene s = scene("dam_break.json", {"fluid.spacing=0.02", "time.end_frame=7", "time.dt_max=0.02",
                                           "time.cfl_factor=1.0"});
  SimulationOptions o;
  o.progress = false;
  const fs::path a = freshDir("a"), b = freshDir("b"), c = freshDir("c");
  o.shotDir = a.string();
  simulateShot(s, o);
  o.shotDir = b.string();
  simulateShot(s, o);
  Scene shorter = s;
  shorter.time.endFrame = 4;
  o.shotDir = c.string();
  simulateShot(shorter, o);
  o.resume = true;
  simulateShot(s, o);
  for (int frame = s.time.startFrame; frame <= s.time.endFrame; ++frame) {
    const std::string ca = readBytes(particleCachePath(a.string(), frame));
    ASSERT_FALSE(ca.empty()) << frame;
    EXPECT_EQ(ca, readBytes(particleCachePath(b.string(), frame))) << "rerun differs at frame " << frame;
    EXPECT_EQ(ca, readBytes(particleCachePath(c.string(), frame))) << "resume differs at frame " << frame;
  }
}

// A box collider rising through the fluid: the run stays healthy and no particle ends up inside it.
TEST_F(DFSPH, MovingColliderPushesFluidWithoutPenetration) {
  const Scene s = scene("box_emerge.json",
                        {"fluid.spacing=0.04", "time.start_frame=1", "time.end_frame=13", "time.dt_max=0.01",
                         R"(colliders.0.keyframes=[{"time":0,"offset":[0,0,0]},)"
                         R"({"time":0.5,"offset":[0,0.3,0]}])"});
  Simulator sim(s);
  while (sim.frame() < s.time.endFrame) sim.advance();
  const ParticleFrame f = sim.cacheFrame();
  const auto& box = s.colliders[0];
  const double lift = 0.3, inset = 0.5 * s.fluid.spacing;
  int inside = 0;
  for (const auto& p : f.position) {
    bool in = true;
    for (int k = 0; k < 3; ++k) {
      const double off = k == 1 ? lift : 0.0;
      in = in && p[k] > box.min[k] + off + inset && p[k] < box.max[k] + off - inset;
    }
    inside += in ? 1 : 0;
  }
  EXPECT_EQ(inside, 0);
}

}  // namespace
}  // namespace sphfx::sim
