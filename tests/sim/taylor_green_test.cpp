// The decaying Taylor-Green vortex (studies/scenes/taylor_green.json, periodic in x, y and z): the
// amplitude of the mode against U0 exp(-8 pi^2 nu t / L^2) (Taylor & Green 1937), with a tolerance that
// follows from the SPH viscosity operator's own error at each resolution (frozenLatticeRate() below),
// and the finer resolution closer to the reference than the coarser.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gpu_types.h"
#include "metrics.h"
#include "references.h"
#include "sim_test_util.h"
#include "simulator.h"

using namespace sphfx;

namespace {

/// The decay rate of the Taylor-Green mode under the solver's viscosity term on the initial lattice
/// (particles frozen there, every density rho0), relative to the exact nu (kx^2 + kz^2):
///   a_i = nu sum_j (m / rho0) (v_j - v_i) lap W(r_ij), lap W = 45 / (pi h^6) (h - r) (Mueller et al. 2003),
/// m the calibrated particle mass (sim::calibratedParticleMass: the Wendland C2 density sum of the
/// lattice is rho0). For the mode, v_j - v_i = (cos(kx dx) cos(kz dz) - 1) v_i, so the rate is
///   -nu (m / rho0) sum_j (cos(kx dx) cos(kz dz) - 1) lap W(r_j).
/// Its error has two parts: the lattice sum of r^2 lap W / 6 is not 1 (0.956 at h = 2 s: -4.4 % at any
/// spacing, shrinking only as h / s grows), and the kernel smooths the mode (-O((k h)^2): -7.6 % more at
/// L = 10 s, -1.9 % at L = 20 s).
double frozenLatticeRate(const Scene& scene) {
  const double s = scene.fluid.spacing, h = scene.kernelRadius();
  const double lx = scene.domain.max[0] - scene.domain.min[0], lz = scene.domain.max[2] - scene.domain.min[2];
  const double kx = 2 * M_PI / lx, kz = 2 * M_PI / lz;
  const double volume = sim::calibratedParticleMass(scene) / scene.fluid.restDensity;
  const int n = int(std::ceil(h / s));
  double sum = 0;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const double r = s * std::sqrt(double(i * i + j * j + k * k));
        if (r >= h) continue;
        const double lap = 45.0 / (M_PI * std::pow(h, 6)) * (h - r);
        sum += (std::cos(kx * i * s) * std::cos(kz * k * s) - 1) * lap;
      }
  return -volume * sum / (kx * kx + kz * kz);
}

struct TaylorGreenRun {
  double latticeRate = 0;        ///< frozenLatticeRate()
  double dtMean = 0;             ///< mean step over the run (s)
  double rate = 0;               ///< fitted decay rate of the mode / nu (kx^2 + kz^2)
  double worst = 0;              ///< largest |U / U_ref - 1| over the frames
  double worstPredicted = 0;     ///< the same for the predicted rate (lattice and time step)
  double predictedRate = 0;      ///< the frozen lattice's rate under the run's time step / exact
  double sigmaTEnd = 0;          ///< nu (kx^2 + kz^2) t at the last frame
  double resolution = 0;         ///< L / spacing
  int unconverged = 0;           ///< DFSPH constant-density solves stopped above their tolerance
  bool decaysEveryFrame = true;  ///< 0 < U and U below the last frame's in every frame
};

TaylorGreenRun runTaylorGreen(const std::string& method, double spacing, std::vector<std::string> sets = {}) {
  sets.push_back(fmt::format("fluid.spacing={}", spacing));
  sets.push_back("solver.method=" + method);
  const Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/studies/scenes/taylor_green.json", sets);
  const Domain& d = scene.domain;
  const double lx = d.max[0] - d.min[0], lz = d.max[2] - d.min[2], nu = scene.fluid.viscosity;
  const double U0 = scene.fluid.blocks.front().taylorGreen->amplitude;
  const double sigma = nu * 4 * M_PI * M_PI * (1 / (lx * lx) + 1 / (lz * lz));
  TaylorGreenRun run;
  run.latticeRate = frozenLatticeRate(scene);
  sim::Simulator sim(scene);
  std::vector<std::pair<double, double>> samples;  // (t, U)
  double dtSum = 0;
  int steps = 0;
  for (;;) {
    const ParticleFrame f = sim.cacheFrame();
    samples.emplace_back(f.time, study::taylorGreenModeAmplitude(f, d.min[0], d.min[2], lx, lz));
    if (sim.frame() >= scene.time.endFrame) break;
    const sim::FrameStats stats = sim.advance();
    for (const auto& [name, value] : stats.solverStats)
      if (name == "pressure_unconverged") run.unconverged += int(value);
    dtSum += stats.dtMean * stats.substeps;
    steps += stats.substeps;
  }
  run.dtMean = dtSum / steps;
  // Symplectic Euler is explicit in the viscous term: each step multiplies the mode by 1 - rate dt, a
  // rate of -log(1 - rate dt) / dt.
  const double lattice = run.latticeRate * sigma;
  const double predicted = -std::log(1 - lattice * run.dtMean) / run.dtMean / sigma;
  run.predictedRate = predicted;
  run.sigmaTEnd = sigma * samples.back().first;
  run.resolution = lx / spacing;
  double st = 0, sy = 0, stt = 0, sty = 0;
  for (size_t k = 1; k < samples.size(); ++k)
    run.decaysEveryFrame =
        run.decaysEveryFrame && samples[k].second > 0 && samples[k].second < samples[k - 1].second;
  for (const auto& [t, U] : samples) {
    st += t, sy += std::log(U), stt += t * t, sty += t * std::log(U);
    if (t <= 0) continue;
    run.worst = std::max(run.worst, std::fabs(U / study::taylorGreenAmplitude(U0, t, lx, lz, nu) - 1));
    run.worstPredicted =
        std::max(run.worstPredicted, std::fabs(U / (U0 * std::exp(-predicted * sigma * t)) - 1));
  }
  const double n = double(samples.size());
  run.rate = -(n * sty - st * sy) / (n * stt - st * st) / sigma;
  std::printf(
      "%s L/%.0f: %u particles, mean dt %.3g s; decay rate / exact %.4f (frozen lattice %.4f, with the "
      "time step %.4f); max |U/U_ref - 1| %.4f (against the predicted decay %.4f)\n",
      method.c_str(), lx / spacing, sim.particleCount(), run.dtMean, run.rate, run.latticeRate, predicted,
      run.worst, run.worstPredicted);
  return run;
}

// The scene's Reynolds number U0 L / nu is 0.1 (U0 = 1 mm/s): the particles move at most
// U0 (1 - exp(-sigma t_end)) / sigma = 0.08 mm (0.008 s at L/10, 0.016 s at L/20) in the run, so the
// lattice the prediction is derived on stays the particles' arrangement. (At U0 L / nu = 1 and above the
// particles' drift off the lattice adds decay that grows with time and resolution: docs/validation.md,
// "Known limits".) Both solvers share the viscosity operator and the step's explicit viscous update; the
// mode is divergence-free on the lattice too, so DFSPH's solves leave it alone.
void expectExponentialDecay(const std::string& method) {
  const double L = 0.1;
  const TaylorGreenRun coarse = runTaylorGreen(method, L / 10), fine = runTaylorGreen(method, L / 20);
  for (const TaylorGreenRun* run : {&coarse, &fine}) {
    // The solver's decay rate is the frozen lattice's under symplectic Euler (predictedRate). Left out
    // of the prediction: the lattice's shear by the particles' motion (first order in the displacement
    // per spacing, <= 0.016 here) and WCSPH's acoustic transient at the start (orthogonal to the mode):
    // 0.02.
    EXPECT_NEAR(run->rate, run->predictedRate, 0.02) << method << " spacing L/" << run->resolution;
    // Against the exact decay, the amplitude may be off by the predicted rate error and that margin
    // accumulated over the run: exp((|1 - predicted| + 0.02) sigma t_end) - 1.
    const double bound = std::exp((std::fabs(1 - run->predictedRate) + 0.02) * run->sigmaTEnd) - 1;
    EXPECT_LT(run->worst, bound) << method << " spacing L/" << run->resolution;
    std::printf("%s L/%.0f: rate %.4f against predicted %.4f +- 0.02; max |U/U_ref - 1| %.4f < %.4f\n",
                method.c_str(), run->resolution, run->rate, run->predictedRate, run->worst, bound);
  }
  // The kernel's smoothing of the mode falls as (k h)^2: the finer run must be closer to the exact rate.
  EXPECT_LT(std::fabs(fine.rate - 1), std::fabs(coarse.rate - 1)) << method;
}

class TaylorGreen : public test::SolverTest {};

TEST_P(TaylorGreen, VortexDecaysAsExpMinus8Pi2NuTOverL2) {
  expectExponentialDecay(GetParam());
}

INSTANTIATE_TEST_SUITE_P(Solvers, TaylorGreen, ::testing::Values("wcsph", "dfsph"), test::solverParamName);

// At U0 L / nu = 10 (U0 = 0.1 m/s) the particles travel up to U0 (1 - exp(-sigma t_end)) / sigma = 7.9 mm,
// 1.2 spacings at L/15, and leave the lattice, whose kernel sum the rest density was calibrated on: the
// mean density of the fixed periodic volume drifts off rest, and a constant-density solve that targets
// rest cannot converge (no correction changes the mean). DFSPH targets the mean there
// (DFSPH_CLOSED_PERIODIC). At kernel support 3 (at 2 both solvers lose the mode at this Reynolds number:
// validation.md) the mode then decays in every frame, every solve meets its tolerance, and the finer
// run's decay rate is closer to the exact one.
TEST(TaylorGreenClosedPeriodic, DfsphDecaysAtReynolds10) {
  const auto context = test::makeContext();
  const double L = 0.1;
  const std::vector<std::string> sets = {"fluid.blocks.0.taylor_green.amplitude=0.1",
                                         "solver.kernel_support=3"};
  const TaylorGreenRun coarse = runTaylorGreen("dfsph", L / 15, sets),
                       fine = runTaylorGreen("dfsph", L / 20, sets);
  for (const TaylorGreenRun* run : {&coarse, &fine}) {
    EXPECT_EQ(run->unconverged, 0) << "spacing L/" << run->resolution;
    EXPECT_TRUE(run->decaysEveryFrame) << "spacing L/" << run->resolution;
  }
  EXPECT_LT(std::fabs(fine.rate - 1), std::fabs(coarse.rate - 1));
  std::printf("decay rate / exact: L/15 %.4f, L/20 %.4f\n", coarse.rate, fine.rate);
}

}  // namespace
