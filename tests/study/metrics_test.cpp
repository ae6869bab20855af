// Metrics on synthetic frames whose answers are known by construction.
#include <gtest/gtest.h>

#include <cmath>

#include "metrics.h"
#include "sphfx/core/error.h"
#include "sphfx/core/scene.h"
#include "sphfx/study/study.h"

using namespace sphfx;
using namespace sphfx::study;

namespace {
ParticleFrame lattice(int nx, int ny, int nz, double d) {
  ParticleFrame f;
  f.particleSpacing = d;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        f.position.push_back({float((i + 0.5) * d), float((j + 0.5) * d), float((k + 0.5) * d)});
        f.velocity.push_back({0, 0, 0});
      }
  return f;
}
}  // namespace

TEST(Metrics, SurgeFrontAndColumnHeightOfABlock) {
  const ParticleFrame f = lattice(20, 40, 5, 0.01);  // a 0.2 x 0.4 block at x = 0
  EXPECT_NEAR(surgeFront(f, 0.0), 0.2, 1e-6);
  EXPECT_NEAR(columnHeightAtWall(f, 0.0, 0.02), 0.4, 1e-6);
  ParticleFrame stray = f;
  stray.position.push_back({5.0f, 0.0f, 0.0f});  // one droplet far ahead does not move the front
  stray.velocity.push_back({0, 0, 0});
  EXPECT_NEAR(surgeFront(stray, 0.0), 0.2, 1e-6);
  stray.position.push_back({0.005f, 1.0f, 0.0f});  // nor does a droplet falling past the wall set the height
  stray.velocity.push_back({0, 0, 0});
  EXPECT_NEAR(columnHeightAtWall(stray, 0.0, 0.02), 0.4, 1e-6);
}

TEST(Metrics, RelativeErrorOfACurve) {
  const Table ref({0, 1, 2}, {1, 2, 3});
  const std::vector<CurveSample> sim = {
      {0.5, 1.5 * 1.1}, {1.5, 2.5 * 0.9}, {2.5, 100}};  // last sample outside
  const CurveError e = relativeError(sim, ref, 10);
  EXPECT_EQ(e.samples, 2u);
  EXPECT_NEAR(e.rms, 0.1, 1e-12);
  EXPECT_NEAR(e.max, 0.1, 1e-12);
  EXPECT_EQ(relativeError(sim, ref, 1.0).samples, 1u);
}

TEST(Metrics, HydrostaticErrorIsZeroForTheExactProfile) {
  ParticleFrame f = lattice(4, 30, 4, 0.01);
  const double H = 0.3, rho0 = 1000, g = 9.81;
  for (const auto& p : f.position) {
    f.density.push_back(float(rho0));
    f.pressure.push_back(float(rho0 * g * (H - p[1])));
  }
  HydrostaticError e = hydrostaticError(f, rho0, g, H, 0.02);
  EXPECT_LT(e.pressureL2, 1e-6);
  EXPECT_NEAR(e.meanDensityError, 0, 1e-9);
  EXPECT_LT(e.profileL2, 1e-6);
  for (auto& p : f.pressure) p *= 1.05f;
  EXPECT_NEAR(hydrostaticError(f, rho0, g, H, 0.02).pressureL2, 0.05, 1e-4);
  EXPECT_NEAR(hydrostaticError(f, rho0, g, H, 0.02).profileL2, 0.05, 1e-4);
  // Noise that averages out over a layer (alternate particles +-10 %) is in the particles' norm only.
  for (size_t i = 0; i < f.size(); ++i)
    f.pressure[i] = float(rho0 * g * (H - f.position[i][1]) * (i % 2 ? 1.1 : 0.9));
  e = hydrostaticError(f, rho0, g, H, 0.02);
  EXPECT_NEAR(e.pressureL2, 0.1, 1e-4);
  EXPECT_LT(e.profileL2, 1e-6);
  f.density.clear();
  EXPECT_THROW(hydrostaticError(f, rho0, g, H, 0.02), InputError);
}

// A column ringing about the hydrostatic profile: frames 10 % above and 10 % below it average to it.
TEST(Metrics, PressureSlabsAverageFramesOverTime) {
  const double H = 0.3, rho0 = 1000, g = 9.81;
  ParticleFrame high = lattice(4, 30, 4, 0.01), low = high;
  for (const auto& p : high.position) {
    high.pressure.push_back(float(1.1 * rho0 * g * (H - p[1])));
    low.pressure.push_back(float(0.9 * rho0 * g * (H - p[1])));
  }
  PressureSlabs slabs(rho0, g, H, 0.02);
  slabs.add(high);
  EXPECT_NEAR(slabs.profileError(), 0.1, 1e-5);
  slabs.add(low);
  EXPECT_LT(slabs.profileError(), 1e-6);
  const std::vector<double> r = slabs.ratios();
  ASSERT_EQ(r.size(), 28u);  // slabs 0.01 m high up to H - h = 0.28 m
  for (double x : r) EXPECT_NEAR(x, 1.0, 1e-6);
  low.pressure.clear();
  EXPECT_THROW(slabs.add(low), InputError);
}

TEST(Metrics, PoiseuilleProfileErrorOfTheExactSolutionIsSmall) {
  const double L = 1e-3, F = 1e-4, nu = 1e-6;
  ParticleFrame f = lattice(4, 40, 1, L / 40);
  f.time = 0.02;
  for (size_t i = 0; i < f.size(); ++i)
    f.velocity[i][0] = float(poiseuilleVelocity(f.position[i][1], f.time, L, F, nu));
  EXPECT_LT(poiseuilleProfileError(f, L, F, nu, 20), 1e-5);
  for (auto& v : f.velocity) v[0] *= 0.9f;
  EXPECT_NEAR(poiseuilleProfileError(f, L, F, nu, 20), 0.1, 1e-3);
}

TEST(Metrics, Energies) {
  ParticleFrame f = lattice(1, 1, 1, 1.0);
  f.velocity[0] = {3, 4, 0};
  EXPECT_DOUBLE_EQ(kineticEnergy(f, 2.0), 25.0);
  EXPECT_DOUBLE_EQ(potentialEnergy(f, 2.0, 10.0), 2.0 * 10.0 * 0.5);
}

TEST(Metrics, ObservedOrderRecoversThePower) {
  std::vector<std::pair<double, double>> he;
  for (double h : {0.04, 0.02, 0.01}) he.emplace_back(h, 3.0 * h * h);
  EXPECT_NEAR(observedOrder(he), 2.0, 1e-12);
  EXPECT_THROW(observedOrder({{0.1, 1}}), InputError);
  EXPECT_THROW(observedOrder({{0.1, 1}, {0.1, 2}}), InputError);
}

TEST(Metrics, ParetoFront) {
  // (cost, error): 0 and 2 and 3 are optimal; 1 is beaten by 0; 4 ties 3 on error but costs more.
  const std::vector<std::pair<double, double>> pts = {{1, 5}, {2, 6}, {3, 2}, {10, 1}, {11, 1}};
  EXPECT_EQ(paretoFront(pts), (std::vector<size_t>{0, 2, 3}));
}

TEST(Metrics, TaylorGreenModeAmplitudeIgnoresOtherModes) {
  // A lattice filling a 0.2 x 0.1 (x, z) period from (0.05, 0.02): the seeded vortex of amplitude U plus a
  // uniform drift and a compressive 2k wave (the start's acoustic transient) fits back to U.
  sphfx::Domain d;
  d.min = {0.05, 0, 0.02};
  d.max = {0.25, 0.04, 0.12};
  ParticleFrame f = lattice(40, 4, 20, 0.005);
  const double U = 0.003;
  for (size_t i = 0; i < f.size(); ++i) {
    auto& p = f.position[i];
    p[0] += float(d.min[0]);
    p[2] += float(d.min[2]);
    const auto v = sphfx::taylorGreenVelocity(d, U, {p[0], p[1], p[2]});
    const double wave = 0.002 * std::sin(4 * M_PI * (p[0] - d.min[0]) / 0.2);
    f.velocity[i] = {float(v[0] + 0.01 + wave), float(v[1]), float(v[2] - 0.004)};
  }
  EXPECT_NEAR(taylorGreenModeAmplitude(f, d.min[0], d.min[2], 0.2, 0.1), U, 1e-4 * U);  // float state
}

// The dam break's self-convergence metric on synthetic fronts: a reference x_ref = a + t (a = 0.2 m, far
// wall at 1 m) and a run x = a + 1.1 t are 10 % apart in surge distance at every frame, so "front_self"
// is 0.1; frames before 0.05 s and after the reference front passes 0.9 m are left out (a run that is off
// only there scores 0). Each solver's runs are measured against that solver's finest run, which itself
// gets no value.
TEST(Metrics, FrontSelfConvergenceAgainstTheFinestRunOfEachSeries) {
  const Scene scene = parseScene(schema::Json::parse(R"({
    "domain": { "min": [0, 0, 0], "max": [1.0, 0.5, 0.06] },
    "fluid": { "spacing": 0.01, "blocks": [ { "shape": "box", "min": [0, 0, 0], "max": [0.2, 0.4, 0.06] } ] }
  })"),
                                 "dam");
  StudyCase c;
  c.validation = Validation::DamBreak;
  c.convergenceAxis = "fluid.spacing";
  auto run = [](const std::string& solver, const std::string& spacing, auto front) {
    RunResult r;
    r.parameters = {{"solver.method", solver}, {"fluid.spacing", spacing}};
    r.outcome.status = RunStatus::Completed;
    for (int k = 0; k <= 100; ++k) {
      const double t = k * 0.01;
      r.front.emplace_back(t, front(t));
    }
    return r;
  };
  RunResult fine = run("wcsph", "0.005", [](double t) { return 0.2 + t; });
  RunResult coarse = run("wcsph", "0.01", [](double t) { return 0.2 + 1.1 * t; });
  RunResult offOnlyOutside =
      run("wcsph", "0.02", [](double t) { return t < 0.045 || t > 0.75 ? 0.2 + 2 * t : 0.2 + t; });
  RunResult otherFine = run("dfsph", "0.0075", [](double t) { return 0.2 + 0.5 * t; });
  RunResult otherCoarse = run("dfsph", "0.015", [](double t) { return 0.2 + 0.45 * t; });
  addFrontSelfConvergence(c, scene, {&fine, &coarse, &offOnlyOutside, &otherFine, &otherCoarse});
  EXPECT_EQ(fine.metrics.count("front_self"), 0u);
  EXPECT_EQ(otherFine.metrics.count("front_self"), 0u);
  EXPECT_NEAR(coarse.metrics.at("front_self"), 0.1, 1e-9);
  EXPECT_NEAR(offOnlyOutside.metrics.at("front_self"), 0.0, 1e-12);
  EXPECT_NEAR(otherCoarse.metrics.at("front_self"), 0.1, 1e-9);
}
