// Periodic boundaries (domain.periodic): neighbour sets across the seams against a brute-force CPU
// minimum-image search, momentum and particle count conserved with nothing leaving [min, max), a uniform
// flow that must stay a pure translation, and plane Poiseuille flow against the series solution of
// Morris, Fox & Zhu (1997).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bindings.h"
#include "boundary_akinci2012.h"
#include "gpu_types.h"
#include "metrics.h"
#include "neighbor_grid.h"
#include "sim_test_util.h"
#include "simulator.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"

using namespace sphfx;
using Vec4 = std::array<float, 4>;

namespace {

// ---------------------------------------------------------------------------------------------------
// Neighbour search

/// Squared minimum-image distance on the CPU, in double.
double minImageDistance2(const Scene& scene, const Vec4& a, const Vec4& b) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    double d = double(a[k]) - double(b[k]);
    if (scene.domain.isPeriodic(k)) {
      const double len = scene.domain.max[k] - scene.domain.min[k];
      d -= len * std::round(d / len);
    }
    d2 += d * d;
  }
  return d2;
}

/// Random items in the domain, a third of them within h of a periodic face (pairs across the seam).
std::vector<Vec4> seamItems(const Scene& scene, int count, unsigned seed) {
  const double h = scene.kernelRadius();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec4> items;
  for (int i = 0; i < count; ++i) {
    Vec4 p{};
    for (int k = 0; k < 3; ++k) {
      const double lo = scene.domain.min[k], hi = scene.domain.max[k];
      double x = lo + (hi - lo) * u(rng);
      if (i % 3 == 0 && scene.domain.isPeriodic(k)) x = u(rng) < 0.5 ? lo + h * u(rng) : hi - h * u(rng);
      p[k] = std::min(float(x), std::nextafter(float(hi), -1e30f));  // [min, max) as the integration keeps
    }
    p[3] = std::bit_cast<float>(uint32_t(i));
    items.push_back(p);
  }
  return items;
}

void expectNeighboursMatchBruteForce(const Scene& scene, const std::vector<Vec4>& items) {
  const double h2 = scene.kernelRadius() * scene.kernelRadius();
  size_t seamPairs = 0, ambiguous = 0;
  for (const auto& [id, found] : test::gpuNeighbours(scene, items)) {
    for (uint32_t j = 0; j < items.size(); ++j) {
      const double d2 = minImageDistance2(scene, items[id], items[j]);
      // Pairs within float rounding of h are decided differently by the float GPU test: not compared.
      if (std::fabs(d2 - h2) < 1e-5 * h2) {
        ++ambiguous;
        continue;
      }
      ASSERT_EQ(found.count(j) == 1, d2 < h2) << "item " << id << ", candidate " << j << ", distance "
                                              << std::sqrt(d2) << ", h " << std::sqrt(h2);
      double direct = 0;
      for (int k = 0; k < 3; ++k)
        direct += (double(items[id][k]) - items[j][k]) * (items[id][k] - items[j][k]);
      if (d2 < h2 && direct >= h2) ++seamPairs;
    }
  }
  std::printf("%zu items, %zu neighbour pairs only across a seam, %zu pairs within rounding of h skipped\n",
              items.size(), seamPairs, ambiguous);
  EXPECT_GT(seamPairs, items.size()) << "too few pairs across the seam: the test would not test the seam";
}

TEST(Periodic, NeighbourSetsAcrossTheSeamsMatchBruteForce) {
  auto ctx = test::makeContext();
  // Extents that are not whole multiples of h (0.04): the last cell of a periodic axis is wider.
  const Scene both = test::sceneFromJson(
      R"({"domain": {"min": [-0.1,0,0.05], "max": [0.23,0.2,0.19], "periodic": ["x", "z"]},
          "fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0.1], "max": [0.1,0.1,0.15]}]}})");
  ASSERT_EQ(sim::gridDims(both)[0], 8);  // 0.33 / 0.04 = 8.25: 8 cells, the last 0.05 wide
  expectNeighboursMatchBruteForce(both, seamItems(both, 2500, 5));
  // Exactly 3 cells along x (the smallest period allowed), walls in z.
  const Scene xOnly = test::sceneFromJson(
      R"({"domain": {"min": [0,0,0], "max": [0.12,0.2,0.3], "periodic": ["x"]},
          "fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.12,0.1,0.1]}]}})");
  ASSERT_EQ(sim::gridDims(xOnly)[0], 3);
  expectNeighboursMatchBruteForce(xOnly, seamItems(xOnly, 1500, 9));
  // Periodic in z only: the walks cut their rows to slabs in x (sim::gridSplitX()), but not across
  // the z seam, where the last cell is wider (0.14 / 0.04: 3 cells, the last 0.06 wide).
  const Scene zOnly = test::sceneFromJson(
      R"({"domain": {"min": [0,0,0], "max": [0.3,0.2,0.14], "periodic": ["z"]},
          "fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.1,0.1,0.14]}]}})");
  ASSERT_EQ(sim::gridSplitX(zOnly), 4);
  ASSERT_EQ(sim::gridSplitX(both), 1);
  expectNeighboursMatchBruteForce(zOnly, seamItems(zOnly, 2000, 13));
  // Periodic in y (no gravity): rows wrap in y as in z, with the slabs in x (split 4) and with every
  // axis wrapped (no walls at all; the y period 3 cells, the last wider: 0.13 / 0.04).
  const Scene yOnly = test::sceneFromJson(
      R"({"domain": {"min": [0,0,0], "max": [0.3,0.14,0.2], "periodic": ["y"]}, "gravity": [0,0,0],
          "fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.1,0.14,0.1]}]}})");
  ASSERT_EQ(sim::gridSplitX(yOnly), 4);
  expectNeighboursMatchBruteForce(yOnly, seamItems(yOnly, 2000, 17));
  const Scene all = test::sceneFromJson(
      R"({"domain": {"min": [0,-0.05,0], "max": [0.16,0.08,0.12], "periodic": ["x", "y", "z"]},
          "gravity": [0,0,0], "fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.16,0.04,0.12]}]}})");
  ASSERT_EQ(sim::gridDims(all)[1], 3);
  expectNeighboursMatchBruteForce(all, seamItems(all, 800, 19));  // a small box: <= 400 neighbours each
}

TEST(Periodic, WallSamplesOnlyOnTheNonPeriodicFaces) {
  const Scene scene = test::sceneFromJson(
      R"({"domain": {"min": [0,0,0], "max": [0.2,0.3,0.16], "periodic": ["x", "z"]},
          "fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.2,0.1,0.16]}]}})");
  const sim::BoundarySamples samples = sim::sampleBoundaries(scene);
  const int layers = sim::boundaryLayers(scene);
  // Two slabs (below and above the domain in y), each 10 x 8 lattice cells, `layers` deep.
  ASSERT_EQ(samples.size(), size_t(2 * layers * 10 * 8));
  for (const auto& s : samples.rest) {
    EXPECT_TRUE(s[0] > 0 && s[0] < 0.2f && s[2] > 0 && s[2] < 0.16f);
    EXPECT_TRUE(s[1] < 0 || s[1] > 0.3f);
  }
}

TEST(Periodic, SceneChecks) {
  auto load = [](const std::string& domainExtra, const std::string& solver) {
    return test::sceneFromJson(
        R"({"domain": {"min": [0,0,0], "max": [0.2,0.2,0.2])" + domainExtra + R"(}, "solver": {"method": ")" +
        solver + R"("}, "fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.2,0.1,0.2]}]}})");
  };
  EXPECT_NO_THROW(load(R"(, "periodic": ["x"])", "wcsph"));
  EXPECT_TRUE(load(R"(, "periodic": ["z", "x"])", "wcsph").domain.isPeriodic(2));
  EXPECT_FALSE(load("", "wcsph").domain.anyPeriodic());
  EXPECT_TRUE(load(R"(, "periodic": ["x", "z"])", "dfsph").domain.isPeriodic(0));
}

// ---------------------------------------------------------------------------------------------------
// Dynamics

bool insideHalfOpen(const Scene& s, const ParticleFrame& f) {
  for (const auto& p : f.position)
    for (int a = 0; a < 3; ++a) {
      if (!(p[a] >= s.domain.min[a] && p[a] <= s.domain.max[a])) return false;
      if (s.domain.isPeriodic(a) && !(p[a] < s.domain.max[a])) return false;
    }
  return true;
}

// Two blocks moving towards each other only across the x seam (at x = 0 = 0.24; inside the box they
// move apart), and across the z seam; no gravity, walls out of reach in y. The pressure force (WCSPH's,
// or DFSPH's symmetric stiffness corrections) and artificial viscosity are pairwise antisymmetric, so
// momentum must stay at its start: a seam seen from one side only would break that. The blocks must also
// have collided (else nothing was tested).
void expectMomentumConservedAcrossTheSeams(const std::string& method) {
  SCOPED_TRACE(method);
  const Scene scene = test::sceneFromJson(R"({"solver": {"method": ")" + method + R"("},
      "domain": {"min": [0,0,0], "max": [0.24,0.6,0.16], "periodic": ["x", "z"]}, "gravity": [0,0,0],
      "fluid": {"spacing": 0.02, "blocks": [
        {"min": [0.02,0.24,0], "max": [0.1,0.36,0.16], "velocity": [-0.4, 0, 0.4]},
        {"min": [0.14,0.24,0], "max": [0.22,0.36,0.16], "velocity": [0.3, 0.1, 0.4]}]},
      "time": {"fps": 50, "start_frame": 1, "end_frame": 11}, "cache": {"attributes": ["id"]}})");
  sim::Simulator sim(scene);
  const ParticleFrame f0 = sim.cacheFrame();
  const auto p0 = test::momentum(f0);
  const size_t firstBlock = f0.size() / 2;  // ids [0, n/2): the block moving in -x
  double vmax = 0, yLow = 1, yHigh = 0;
  ParticleFrame f1;
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    f1 = sim.cacheFrame();
    ASSERT_EQ(f1.size(), f0.size());
    ASSERT_TRUE(insideHalfOpen(scene, f1)) << "frame " << f1.frame;
    for (size_t i = 0; i < f1.size(); ++i) {
      vmax = std::max(vmax, double(std::hypot(f1.velocity[i][0], f1.velocity[i][1], f1.velocity[i][2])));
      yLow = std::min(yLow, double(f1.position[i][1]));
      yHigh = std::max(yHigh, double(f1.position[i][1]));
    }
  }
  const std::set<int32_t> ids(f1.id.begin(), f1.id.end());
  EXPECT_EQ(ids.size(), f0.size()) << "particles lost or duplicated";
  double firstVx = 0;
  for (size_t i = 0; i < f1.size(); ++i)
    if (size_t(f1.id[i]) < firstBlock) firstVx += f1.velocity[i][0] / double(firstBlock);
  std::printf("%s: first block mean vx: -0.4 -> %.3f m/s; y range [%.3f, %.3f]\n", method.c_str(), firstVx,
              yLow, yHigh);
  EXPECT_GT(firstVx, -0.3) << "the blocks did not collide across the seam";
  // Walls out of reach throughout (else their forces would change the momentum legitimately).
  EXPECT_GT(yLow, scene.kernelRadius());
  EXPECT_LT(yHigh, scene.domain.max[1] - scene.kernelRadius());
  const auto p1 = test::momentum(f1);
  for (int a = 0; a < 3; ++a) {
    // Float precision as in Physics.MomentumConservedWithoutGravityOrWalls.
    const double tolerance = 1e-4 * double(f1.size()) * vmax;
    EXPECT_NEAR(p1[a], p0[a], tolerance) << "axis " << a;
    std::printf("momentum axis %d: %.6g -> %.6g (|dP| / (N vmax) = %.2e)\n", a, p0[a], p1[a],
                std::fabs(p1[a] - p0[a]) / (double(f1.size()) * vmax));
  }
}

/// Density per particle id of each frame of a slab run (frames 1..end).
std::vector<std::map<int32_t, float>> slabDensities(const Scene& scene) {
  sim::Simulator sim(scene);
  std::vector<std::map<int32_t, float>> frames;
  for (;;) {
    const ParticleFrame f = sim.cacheFrame();
    EXPECT_TRUE(insideHalfOpen(scene, f)) << "frame " << f.frame;
    std::map<int32_t, float> m;
    for (size_t i = 0; i < f.size(); ++i) m[f.id[i]] = f.density[i];
    frames.push_back(std::move(m));
    if (sim.frame() >= scene.time.endFrame) break;
    sim.advance();
  }
  return frames;
}

void expectUniformFlowStaysUniform(const std::string& method) {
  SCOPED_TRACE(method);
  // A slab filling the period in x and z, away from the y walls, no gravity, every particle at the same
  // velocity: the exact solution is a translation of the same slab at rest (Galilean invariance), so
  // each particle's density must equal that of the same particle in a run at rest, frame by frame, while
  // the slab moves through both seams (1.25 periods in x). The slab at rest is not quite static (its y
  // surfaces relax), hence the comparison with it rather than with the start; fixed dt makes both runs
  // take the same steps. A missing or doubled cell across a seam changes the density of the particles
  // next to it by >= 10 % (a row of cells holds about a third of a particle's neighbours).
  const std::string common = R"({"solver": {"method": ")" + method + R"("},
      "domain": {"min": [0,0,0], "max": [0.16,0.4,0.12], "periodic": ["x", "z"]}, "gravity": [0,0,0],
      "time": {"fps": 20, "start_frame": 1, "end_frame": 5, "dt_mode": "fixed", "dt": 0.0005},
      "cache": {"attributes": ["id", "density"]},
      "fluid": {"spacing": 0.02, "blocks": [{"min": [0,0.14,0], "max": [0.16,0.26,0.12], "velocity": )";
  const Scene moving = test::sceneFromJson(common + "[1.0, 0, -0.37]}]}}");
  const Scene resting = test::sceneFromJson(common + "[0, 0, 0]}]}}");
  const auto a = slabDensities(moving), b = slabDensities(resting);
  ASSERT_EQ(a.size(), b.size());
  // At the start, the particles of one y layer have the same density, next to a seam or not.
  std::map<float, std::pair<float, float>> layer;  // y -> density range
  {
    sim::Simulator sim(moving);
    const ParticleFrame f0 = sim.cacheFrame();
    for (size_t i = 0; i < f0.size(); ++i) {
      auto [it, fresh] = layer.try_emplace(f0.position[i][1], f0.density[i], f0.density[i]);
      it->second.first = std::min(it->second.first, f0.density[i]);
      it->second.second = std::max(it->second.second, f0.density[i]);
    }
  }
  for (const auto& [y, range] : layer) EXPECT_LT(range.second - range.first, 1e-5f * range.second) << y;
  double worst = 0, relax = 0;
  for (size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].size(), b[k].size());
    for (const auto& [id, rho] : a[k]) {
      worst = std::max(worst, std::fabs(double(rho) / b[k].at(id) - 1));
      relax = std::max(relax, std::fabs(double(b[k].at(id)) / b[0].at(id) - 1));
    }
  }
  std::printf(
      "%s: uniform flow over %.2f s: max |rho / rho(at rest) - 1| = %.3g (the resting slab itself "
      "moved %.3g from its start)\n",
      method.c_str(), moving.frameTime(moving.time.endFrame), worst, relax);
  // Float positions are not Galilean invariant: x + dt v rounds differently for each particle (ulp of
  // 0.1 m is 7e-9 m, 400 steps, 0.02 m spacing: up to ~1e-4 strain, ~5e-4 in density). Measured: 4.7e-4
  // here, and 2.0e-4 for the same slab translating at 0.54 m/s in a closed box without periodic axes
  // (walls out of reach). The tolerance sits between that and the >= 10 % of a seam error.
  EXPECT_LT(worst, 2e-3);
}

// A resting layer filling the period in x and z, walls only below and above: every column is the same
// column shifted along the periodic axes, so the bottom layer must rest at the same height next to a seam
// as away from it. DFSPH's constraint walls take each floor sample's rest share from the fluid lattice
// around it, which continues across the seams; counted as ending there, the samples within a kernel
// radius of a seam see less fluid than their rest share and hold their columns higher.
TEST(Periodic, DfsphRestingLayerStaysLevelAcrossTheSeams) {
  auto ctx = test::makeContext();
  const Scene scene = test::sceneFromJson(
      R"({"solver": {"method": "dfsph"},
      "domain": {"min": [0,0,0], "max": [0.2,0.4,0.2], "periodic": ["x", "z"]},
      "fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.2,0.3,0.2]}]},
      "time": {"fps": 20, "start_frame": 1, "end_frame": 21}, "cache": {"attributes": ["id"]}})");
  const double s = scene.fluid.spacing, h = scene.kernelRadius(), L = 0.2;
  sim::Simulator sim(scene);
  std::set<int32_t> bottom;  // the ids of the bottom layer
  {
    const ParticleFrame f0 = sim.cacheFrame();
    for (size_t i = 0; i < f0.size(); ++i)
      if (f0.position[i][1] < s) bottom.insert(f0.id[i]);
  }
  while (sim.frame() < scene.time.endFrame) sim.advance();
  const ParticleFrame f = sim.cacheFrame();
  auto nearSeam = [&](double x) { return x < h || x > L - h; };
  double seam = 0, inner = 0;
  int seamCount = 0, innerCount = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    if (!bottom.count(f.id[i])) continue;
    const auto& p = f.position[i];
    if (nearSeam(p[0]) || nearSeam(p[2]))
      seam += p[1], ++seamCount;
    else
      inner += p[1], ++innerCount;
  }
  ASSERT_GT(seamCount, 0);
  ASSERT_GT(innerCount, 0);
  const double offset = (seam / seamCount - inner / innerCount) / s;
  std::printf(
      "resting periodic layer after %.1f s: bottom layer within h of a seam %.4f s higher than the "
      "%d others (%d particles)\n",
      f.time, offset, innerCount, seamCount);
  EXPECT_LT(std::fabs(offset), 0.01);
}

// ---------------------------------------------------------------------------------------------------
// Plane Poiseuille flow (studies/scenes/poiseuille.json): Morris, Fox & Zhu 1997's case (L = 1e-3 m,
// nu = 1e-6 m^2/s, F = 2e-4 m/s^2) scaled to L = 0.1 m, nu = 0.01 m^2/s, F = 0.02 m/s^2: the same
// Reynolds number F L^3 / (8 nu^2) = 0.025 and the same times t nu / L^2 (L^2 / nu = 1 s in both), with
// kernel factors (h^-9 for poly6) that float can hold at every spacing used.

struct PoiseuilleRun {
  std::map<int, double> error;  // frame -> relative L2 error of the velocity profile
};

PoiseuilleRun runPoiseuille(const std::string& method, double spacing, const std::vector<int>& frames) {
  const Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/studies/scenes/poiseuille.json",
                                {fmt::format("fluid.spacing={}", spacing), "solver.method=" + method});
  const double L = scene.domain.max[1] - scene.domain.min[1], F = scene.gravity[0],
               nu = scene.fluid.viscosity;
  const int bins = std::max(4, int(std::lround(L / spacing / 2)));  // as the study's measurement
  sim::Simulator sim(scene);
  PoiseuilleRun run;
  for (int frame : frames) {
    while (sim.frame() < frame) sim.advance();
    ParticleFrame f = sim.cacheFrame();
    for (auto& p : f.position) p[1] -= float(scene.domain.min[1]);
    run.error[frame] = study::poiseuilleProfileError(f, L, F, nu, bins);
  }
  return run;
}

// Frames at 400/9 fps: t nu / L^2 = 0.0225, 0.045, 0.1125 (Morris et al.'s Fig. 3 times) and 0.495
// (within 1 % of steady).
void expectPoiseuilleProfile(const std::string& method) {
  const std::vector<int> frames = {1, 2, 5, 22};
  const double L = 0.1;
  const std::map<double, PoiseuilleRun> runs = {{L / 10, runPoiseuille(method, L / 10, frames)},
                                                {L / 20, runPoiseuille(method, L / 20, frames)}};
  for (int f : frames) {
    const double coarse = runs.at(L / 10).error.at(f), fine = runs.at(L / 20).error.at(f);
    std::printf("%s t = %.4f s: profile error %.4f (spacing L/10), %.4f (L/20), observed order %.2f\n",
                method.c_str(), f * 0.0225, coarse, fine, std::log(coarse / fine) / std::log(2.0));
    // The wall samples hold zero velocity, so the fluid slips: the no-slip plane lies about half a
    // spacing inside the wall (the profile is the parabola plus a nearly uniform offset). A slip length
    // of one whole spacing s gives the steady profile a relative L2 error of s / (L sqrt(1/30)) =
    // 5.48 s / L: the bound at every time and resolution.
    for (const auto& [s, run] : runs)
      EXPECT_LT(run.error.at(f), 5.48 * s / L) << method << " frame " << f << ", s " << s;
    // Convergence: halving the spacing must cut the error by 30 % or more (observed order >= 0.5).
    EXPECT_LT(fine, 0.7 * coarse) << method << " frame " << f;
  }
}

// Free-slip walls (fluid.wall_viscosity_factor 0): the same channel feels no wall shear, so the body force
// accelerates it as a plug, u = F t in every layer, the free-slip limit of Morris et al.'s problem; the
// no-slip run (factor 1) at the same instant holds the profile near the Poiseuille series (the test
// above), whose mean is a fraction of F t.
TEST(Periodic, FreeSlipWallsLetTheChannelAccelerateAsAPlug) {
  auto ctx = test::makeContext();
  const std::string path = std::string(SPHFX_SOURCE_DIR) + "/studies/scenes/poiseuille.json";
  const double L = 0.1;
  for (double factor : {0.0, 1.0}) {
    const Scene scene = loadScene(path, {fmt::format("fluid.wall_viscosity_factor={}", factor)});
    const double F = scene.gravity[0];
    sim::Simulator sim(scene);
    while (sim.frame() < 5) sim.advance();  // t nu / L^2 = 0.1125
    const ParticleFrame f = sim.cacheFrame();
    const int bins = 5;
    std::vector<double> sum(bins, 0.0);
    std::vector<int> count(bins, 0);
    for (size_t i = 0; i < f.size(); ++i) {
      const int b = std::clamp(int((f.position[i][1] - scene.domain.min[1]) / L * bins), 0, bins - 1);
      sum[size_t(b)] += f.velocity[i][0];
      ++count[size_t(b)];
    }
    const double plug = F * f.time;
    double mean = 0, spread = 0;
    for (int b = 0; b < bins; ++b) {
      const double u = sum[size_t(b)] / count[size_t(b)];
      mean += u / bins;
      spread = std::max(spread, std::fabs(u - plug) / plug);
    }
    std::printf("wall_viscosity_factor %.0f: mean u / (F t) %.4f, worst layer %.4f off F t\n", factor,
                mean / plug, spread);
    if (factor == 0.0) {
      // Nothing but the body force acts along x: every layer at F t (float sums over ~200 steps).
      EXPECT_LT(spread, 0.01);
    } else {
      // The series' mean at t nu / L^2 = 0.1125 is 0.50 F t (the walls take half the momentum); measured
      // 0.61, the slip of about half a spacing at the wall samples (the Poiseuille test above).
      EXPECT_LT(mean / plug, 0.7);
    }
  }
}

// Every dynamics check above for both solvers (DFSPH: the walls' rest shares continue across the seams
// too; the Poiseuille channel has walls in y only and its body force along the periodic x).
class PeriodicFlow : public test::SolverTest {};

TEST_P(PeriodicFlow, MomentumAndParticlesConservedAcrossTheSeams) {
  expectMomentumConservedAcrossTheSeams(GetParam());
}

TEST_P(PeriodicFlow, UniformFlowStaysUniform) {
  expectUniformFlowStaysUniform(GetParam());
}

TEST_P(PeriodicFlow, PoiseuilleProfileFollowsMorrisSeries) {
  expectPoiseuilleProfile(GetParam());
}

INSTANTIATE_TEST_SUITE_P(Solvers, PeriodicFlow, ::testing::Values("wcsph", "dfsph"), test::solverParamName);

}  // namespace
