// Physical checks against independent references: momentum conservation, no escapes, the hydrostatic
// pressure rho g (H - y), and the Martin & Moyce dam-break surge front.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <numeric>
#include <optional>

#include "boundary_akinci2012.h"
#include "gpu_types.h"
#include "sim_test_util.h"
#include "simulator.h"

using namespace sphfx;

namespace {

bool insideDomain(const Scene& s, const ParticleFrame& f) {
  for (const auto& p : f.position)
    for (int a = 0; a < 3; ++a)
      if (!(p[a] >= s.domain.min[a] && p[a] <= s.domain.max[a])) return false;
  return true;
}

// Runs `sim` to the scene's last frame: the kinetic energy per unit mass of each frame after the first.
std::vector<double> kineticPerMassToTheEnd(sim::Simulator& sim, const Scene& scene) {
  std::vector<double> kinetic;
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    const ParticleFrame f = sim.cacheFrame();
    double k = 0;
    for (const auto& v : f.velocity) k += 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    kinetic.push_back(k / double(f.size()));
  }
  return kinetic;
}

// The mean over the last quarter of the frames (at least one), as the stability suite's rest criterion.
// Mean height of the top `perLayer` particles plus half a spacing `s`, as the stability suite measures
// the surface of a column on a lattice.
double topLayerSurface(const ParticleFrame& f, size_t perLayer, double s) {
  std::vector<float> y;
  for (const auto& p : f.position) y.push_back(p[1]);
  std::sort(y.begin(), y.end(), std::greater<float>());
  return std::accumulate(y.begin(), y.begin() + long(perLayer), 0.0) / double(perLayer) + 0.5 * s;
}

double lastQuarterMean(const std::vector<double>& v) {
  const size_t tail = std::max<size_t>(1, v.size() / 4);
  return std::accumulate(v.end() - long(tail), v.end(), 0.0) / double(tail);
}

TEST(Physics, MomentumConservedWithoutGravityOrWalls) {
  auto ctx = test::makeContext();
  // A compressed block (packing 0.95) expands under its own pressure, far from every wall: internal
  // forces are pairwise antisymmetric under either solver, so total momentum must stay at its initial value.
  for (const std::string method : {"wcsph", "dfsph"}) {
    SCOPED_TRACE(method);
    const Scene scene =
        test::sceneFromJson(R"({"domain": {"min": [0,0,0], "max": [1.2,1.2,1.2]}, "gravity": [0,0,0],
        "solver": {"method": ")" +
                            method + R"("},
        "fluid": {"spacing": 0.02, "packing": 0.95, "blocks": [{"min": [0.5,0.5,0.5], "max": [0.7,0.7,0.7],
        "velocity": [0.3, -0.1, 0.2]}]}, "time": {"fps": 60, "start_frame": 1, "end_frame": 4}})");
    sim::Simulator sim(scene);
    const ParticleFrame f0 = sim.cacheFrame();
    const auto p0 = test::momentum(f0);
    double vmax = 0;
    while (sim.frame() < scene.time.endFrame) sim.advance();
    const ParticleFrame f1 = sim.cacheFrame();
    const auto p1 = test::momentum(f1);
    for (const auto& v : f1.velocity) vmax = std::max(vmax, double(std::hypot(v[0], v[1], v[2])));
    EXPECT_GT(vmax, 0.5) << "the block did not expand: the test would not test anything";
    for (int a = 0; a < 3; ++a) {
      // Float precision: N particles, speeds ~vmax, a few hundred substeps of float rounding.
      const double tolerance = 1e-4 * double(f1.size()) * vmax;
      EXPECT_NEAR(p1[a], p0[a], tolerance) << "axis " << a << ", N " << f1.size();
      std::printf("%s, momentum axis %d: %.6g -> %.6g (|dP| / (N vmax) = %.2e)\n", method.c_str(), a, p0[a],
                  p1[a], std::fabs(p1[a] - p0[a]) / (double(f1.size()) * vmax));
    }
    EXPECT_TRUE(insideDomain(scene, f1));
  }
}

// A strong artificial viscosity damps the start's sloshing so that the tank settles within the 1 s run;
// the walls' drag is raised with it (alpha c = 0.3 x 30 m/s), or the sloshing along them lasts.
TEST(Physics, HydrostaticTankSettlesToRestDensityAndPressureProfile) {
  auto ctx = test::makeContext();
  const Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/hydrostatic.json",
                                {"solver.method=wcsph", "fluid.spacing=0.02", "time.end_frame=25",
                                 "fluid.artificial_viscosity=0.3", "fluid.wall_viscosity_speed=9"});
  sim::Simulator sim(scene);
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    ASSERT_TRUE(insideDomain(scene, sim.cacheFrame()));
  }
  const ParticleFrame f = sim.cacheFrame();
  // Surface height: the highest particle centre plus half a spacing.
  const double s = scene.fluid.spacing, rho0 = scene.fluid.restDensity, g = -scene.gravity[1],
               h = scene.kernelRadius();
  float top = 0;
  for (const auto& p : f.position) top = std::max(top, p[1]);
  const double H = top + 0.5 * s;
  // Layers two spacings thick: mean pressure and mean height per layer (WCSPH pressure is noisy per
  // particle; the profile is what must match).
  const int layers = int(H / (2 * s)) + 1;
  std::vector<double> pSum(layers), ySum(layers), cnt(layers);
  double rhoSum = 0;
  int n = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    if (f.position[i][1] > H - h) continue;  // the free-surface layer has a deficient neighbourhood
    rhoSum += f.density[i];
    ++n;
    const int l = std::min(layers - 1, int(f.position[i][1] / (2 * s)));
    pSum[l] += f.pressure[i];
    ySum[l] += f.position[i][1];
    cnt[l] += 1;
  }
  double errSum = 0, errMax = 0;
  int used = 0;
  for (int l = 0; l < layers; ++l) {
    if (cnt[l] == 0) continue;
    const double y = ySum[l] / cnt[l], expected = rho0 * g * (H - y);
    const double err = std::fabs(pSum[l] / cnt[l] - expected) / (rho0 * g * H);
    std::printf("  layer y %.3f: p %.1f Pa, rho g (H - y) %.1f Pa\n", y, pSum[l] / cnt[l], expected);
    errSum += err;
    errMax = std::max(errMax, err);
    ++used;
  }
  errSum = errSum / used * n;  // reported below as a mean over layers
  const double meanRho = rhoSum / n;
  std::printf(
      "hydrostatic: H %.4f m, %d interior particles, mean density %.2f (rest %.0f), layer pressure error "
      "vs rho g (H - y): mean %.3f, max %.3f of rho g H\n",
      H, n, meanRho, rho0, errSum / n, errMax);
  EXPECT_NEAR(meanRho / rho0, 1.0, 0.01);
  // Tolerances (docs/simulation.md): measured mean 0.025, max 0.039 of rho g H with the layered lattice
  // boundary; the single-layer Akinci boundary gave a mean of 0.087.
  EXPECT_LT(errSum / n, 0.05);
  EXPECT_LT(errMax, 0.06);
  // Mass conservation: the column keeps its initial fill height (0.30 m) within one spacing (it sank
  // to 0.257 m when the walls were too soft).
  const double fill = scene.fluid.blocks.front().max[1];
  std::printf("surface %.4f m, initial fill %.4f m\n", H, fill);
  EXPECT_NEAR(H, fill, s);
}

// Energy per unit mass, |v|^2 / 2 + g y, and the smallest distance from a particle centre to a wall face.
std::pair<double, double> energyAndWallGap(const Scene& scene, const ParticleFrame& f) {
  double e = 0, gap = 1e9;
  for (size_t i = 0; i < f.size(); ++i) {
    const auto &p = f.position[i], &v = f.velocity[i];
    e += 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - scene.gravity[1] * p[1];
    for (int a = 0; a < 3; ++a) gap = std::min({gap, p[a] - scene.domain.min[a], scene.domain.max[a] - p[a]});
  }
  return {e / double(f.size()), gap};
}

// Runs `scene` to its end frame: the largest gain of the energy per unit mass over its first frame
// (J/kg) and the closest approach of a particle centre to a wall (m), both over every frame.
std::pair<double, double> largestEnergyGainAndClosestWallGap(const Scene& scene) {
  sim::Simulator sim(scene);
  const auto [e0, gap0] = energyAndWallGap(scene, sim.cacheFrame());
  EXPECT_NEAR(gap0, 0.5 * scene.fluid.spacing, 1e-6);
  double growth = -1e9, gap = gap0;
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    const auto [e, g] = energyAndWallGap(scene, sim.cacheFrame());
    growth = std::max(growth, e - e0);
    gap = std::min(gap, g);
  }
  return {growth, gap};
}

TEST(Physics, WcsphWallsDoNotPumpEnergyIntoATankAtRest) {
  auto ctx = test::makeContext();
  // At WCSPH's defaults (Tait, c = 30 m/s, artificial viscosity 0.02): a closed tank at rest can only
  // lose energy. Walls whose pressure is mirrored from each particle gained 2 % of g H in 0.5 s here
  // and threw particles against the floor; the walls' own pressure (sim_boundary_pressure.comp) keeps
  // the pair forces conservative.
  const Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/hydrostatic.json",
                                {"solver.method=wcsph", "fluid.spacing=0.02", "time.end_frame=25"});
  ASSERT_EQ(scene.solver.method, Solver::WCSPH);
  const double s = scene.fluid.spacing, gH = -scene.gravity[1] * scene.fluid.blocks.front().max[1];
  const auto [growth, gap] = largestEnergyGainAndClosestWallGap(scene);
  std::printf("largest energy gain %.3e J/kg (%.3f %% of g H), closest wall approach %.3f s\n", growth,
              100 * growth / gH, gap / s);
  EXPECT_LE(growth, 0.01 * gH);
  EXPECT_GE(gap, 0.1 * s) << "only the last-resort clamp (0.05 s) held a particle";
}

TEST(Physics, WcsphWallPressureFromSharesSummedOnceMatchesSummingEverySubstep) {
  auto ctx = test::makeContext();
  // Without colliders the wall samples' share of each other's density is summed once per run
  // (sim_boundary_pressure.comp); a collider makes every substep sum it again. A resting collider in the
  // top corner, which the surge does not reach in 0.2 s, leaves the wall samples by the fluid as they
  // are, so the two runs must agree; a stale or misplaced share would move the fluid along the walls.
  const std::vector<std::string> base = {"fluid.spacing=0.02", "time.end_frame=7"};
  std::vector<std::string> withCollider = base;
  withCollider.push_back(R"(colliders=[{"shape":"box","min":[0.9,0.5,0],"max":[1.0,0.6,0.1]}])");
  const std::string path = std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json";
  const auto run = [&](const std::vector<std::string>& set) {
    const Scene scene = loadScene(path, set);
    sim::Simulator sim(scene);
    while (sim.frame() < scene.time.endFrame) sim.advance();
    return sim.cacheFrame();
  };
  const ParticleFrame once = run(base), every = run(withCollider);
  ASSERT_EQ(once.size(), every.size());
  double largest = 0, front = 0;
  for (size_t i = 0; i < once.size(); ++i) {
    front = std::max(front, double(once.position[i][0]));
    for (int a = 0; a < 3; ++a)
      largest = std::max(largest, double(std::fabs(once.position[i][a] - every.position[i][a])));
  }
  std::printf("front at x = %.3f m; largest position difference %.3e m\n", front, largest);
  EXPECT_GT(front, 0.4) << "the surge has not run along the floor: the walls were hardly tested";
  EXPECT_LE(largest, 1e-4 * 0.02);
}

TEST(Physics, DfsphConstraintWallsDoNoWorkInAClosedTank) {
  auto ctx = test::makeContext();
  // DFSPH with solver.dfsph.walls "constraints": each wall sample's stiffness pushes the fluid along the
  // gradient of its own density constraint, so the walls' forces do no work and a box filled to its lid
  // at rest can only lose energy (bounded here by a tenth of the suite's 1 % of g H, for the time
  // integration); and the samples hold every particle off the walls. Without the samples' passes the
  // corner particles fall into the corners within a frame.
  const Scene scene =
      loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/hydrostatic.json",
                {"solver.method=dfsph", "solver.dfsph.walls=constraints", "fluid.spacing=0.02",
                 R"(fluid.blocks=[{"shape":"box","min":[0,0,0],"max":[0.2,0.4,0.2]}])", "time.end_frame=25"});
  const double s = scene.fluid.spacing, gH = -scene.gravity[1] * scene.fluid.blocks.front().max[1];
  const auto [growth, gap] = largestEnergyGainAndClosestWallGap(scene);
  std::printf("largest energy gain %.3e J/kg (%.3f %% of g H), closest wall approach %.3f s\n", growth,
              100 * growth / gH, gap / s);
  EXPECT_LE(growth, 0.001 * gH);
  EXPECT_GE(gap, 0.1 * s) << "only the last-resort clamp (0.05 s) held a particle";
}

TEST(Physics, DfsphColumnComesToRestAtTheDefaults) {
  auto ctx = test::makeContext();
  // DFSPH at its defaults: the Wendland C2 density with the constraint walls (the fluid's density is the sum
  // of the kernel whose gradient the solves use, so they correct the density they measure), the depth cap,
  // whose steps start the density solve cold (docs/simulation.md). A column 10 spacings wide and 30 deep at
  // rest, 2 s: over the last quarter, the kinetic energy per unit mass stays under the stability suite's rest
  // bound, 0.5e-4 g H (rms speed 1 % of sqrt(g H)). Under the spiky density the same run with
  // density_warm_share 0.5 in every substep (density_warm_steps "all") ended at 3.1e-4 J/kg, above the bound
  // (1.47e-4); under Wendland C2 at 3.6e-7.
  const Scene scene =
      loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/hydrostatic.json",
                {"solver.method=dfsph", "domain.max=[0.1,0.4,0.1]",
                 R"(fluid.blocks=[{"shape":"box","min":[0,0,0],"max":[0.1,0.3,0.1]}])", "time.end_frame=49"});
  const double gH = -scene.gravity[1] * scene.fluid.blocks.front().max[1];
  sim::Simulator sim(scene);
  const std::vector<double> kinetic = kineticPerMassToTheEnd(sim, scene);
  const size_t tail = std::max<size_t>(1, kinetic.size() / 4);
  const double last = lastQuarterMean(kinetic);
  std::printf("kinetic energy per unit mass over the last %zu frames %.3e J/kg (bound %.3e)\n", tail, last,
              0.5e-4 * gH);
  EXPECT_LT(last, 0.5e-4 * gH);
}

// The resting tank as a column 6 x 60 x 6 spacings (spacing 0.005 m, 2,160 particles), periodic in x and
// z, under DFSPH for 0.5 s, with one more override.
Scene periodicDfsphColumn(const std::string& extra) {
  return loadScene(
      std::string(SPHFX_SOURCE_DIR) + "/scenes/hydrostatic.json",
      {"solver.method=dfsph", extra, "fluid.spacing=0.005", "domain.max=[0.03,0.4,0.03]",
       R"(domain.periodic=["x","z"])",
       R"(fluid.blocks=[{"shape":"box","min":[0,0,0],"max":[0.03,0.3,0.03]}])", "time.end_frame=13"});
}

// A deep resting column under DFSPH with solver.dfsph.density_kernel "wendland_c2" (the default, named so
// that the test keeps it): 60 layers, periodic in x and z (2,160 particles), 0.5 s. Wendland C2 sums lowest
// on the cubic lattice among the cubic, bcc and fcc packings (bench/lattice_sums.py), so the loaded lattice
// holds: the lower third of the column keeps its lattice order (|mean exp(2 pi i x / s)| over its particles,
// 1 on the lattice, 0 where half its rows have shifted half a spacing) above 0.9, and the surface sinks no
// more than the density tolerance lets the layers compress, 0.2 % (the bottom's density error at
// max_density_error 0.1 %) of 60 spacings, 0.12 s, plus settling (bound 0.15 s). The kinetic energy stays
// under the suite's rest bound (0.5e-4 g H). The same test under the spiky kernel fails both: lower third at
// order 0.430, surface 0.342 s down (measured: 1.000 and 0.066 s under Wendland C2; docs/validation.md, Known
// limits).
TEST(Physics, DfsphWendlandColumnKeepsItsLattice) {
  auto ctx = test::makeContext();
  const Scene scene = periodicDfsphColumn("solver.dfsph.density_kernel=wendland_c2");
  const double s = scene.fluid.spacing, gH = -scene.gravity[1] * scene.fluid.blocks.front().max[1];
  const size_t perLayer = 36;  // (0.03 / 0.005)^2
  sim::Simulator sim(scene);
  const double surface0 = topLayerSurface(sim.cacheFrame(), perLayer, s);
  const std::vector<double> kinetic = kineticPerMassToTheEnd(sim, scene);
  const ParticleFrame f = sim.cacheFrame();
  ASSERT_EQ(f.size(), 60 * perLayer);
  std::vector<size_t> order(f.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return f.position[a][1] < f.position[b][1]; });
  const size_t lower = 20 * perLayer;  // the lower third's layers
  double lattice = 1;
  for (int a : {0, 2}) {
    double c = 0, sn = 0;
    for (size_t k = 0; k < lower; ++k) {
      const double phase = 2 * std::numbers::pi * f.position[order[k]][size_t(a)] / s;
      c += std::cos(phase);
      sn += std::sin(phase);
    }
    lattice = std::min(lattice, std::hypot(c, sn) / double(lower));
  }
  const double drift = (surface0 - topLayerSurface(f, perLayer, s)) / s;
  const double last = lastQuarterMean(kinetic);
  std::printf(
      "lower third's lattice order %.3f, surface drift %.3f spacings, KE/m over the last quarter %.3e J/kg\n",
      lattice, drift, last);
  EXPECT_GT(lattice, 0.9);
  EXPECT_LT(std::fabs(drift), 0.15);
  EXPECT_LT(last, 0.5e-4 * gH);
}

// A stiff artificial viscosity under DFSPH: the periodic column above (2,160 particles, 60 layers) at the
// defaults with fluid.artificial_viscosity 0.3, 15 times the default, for 0.5 s. DFSPH's steps follow the
// flow, not the sound speed, so the explicit artificial term needs its own bound, 2 / rate
// (sim::artificialViscosityRate(): 0.40 ms here). With it the column meets the stability suite's rest
// bounds: the kinetic energy over the last quarter under 0.5e-4 g H and the surface within half a spacing
// of its start (measured 5.0e-9 J/kg, 0.010 s). Without it (a build without the bound, the spiky density,
// steps of 0.84 ms) the same run ended at 5.9e-4 J/kg, four times the bound.
TEST(Physics, DfsphStiffArtificialViscosityLeavesTheColumnAtRest) {
  auto ctx = test::makeContext();
  const Scene scene = periodicDfsphColumn("fluid.artificial_viscosity=0.3");
  const double s = scene.fluid.spacing, gH = -scene.gravity[1] * scene.fluid.blocks.front().max[1];
  sim::Simulator sim(scene);
  const double surface0 = topLayerSurface(sim.cacheFrame(), 36, s);
  const std::vector<double> kinetic = kineticPerMassToTheEnd(sim, scene);
  const double drift = (surface0 - topLayerSurface(sim.cacheFrame(), 36, s)) / s;
  const double last = lastQuarterMean(kinetic);
  std::printf("surface drift %.3f spacings, KE/m over the last quarter %.3e J/kg (bound %.3e)\n", drift, last,
              0.5e-4 * gH);
  EXPECT_LT(std::fabs(drift), 0.5);
  EXPECT_LT(last, 0.5e-4 * gH);
}

// Steps that the artificial viscosity's bound (or dt_max) sets below the depth cap: one step's fall
// compresses the column by about g dt^2 / d, less than max_density_error, so with that tolerance the density
// solve stops after a few iterations and the column jitters. Those steps take the tolerance times (step /
// depth step)^2 (sim::dfsphCappedDensityTolerance()), which keeps the ratio of a step's fall to the tolerance
// at the depth cap's. The column of DfsphColumnComesToRestAtTheDefaults (10 x 30 x 10 spacings, 2 s) at
// fluid.artificial_viscosity 0.3 (steps of 0.80 ms against the cap's 2.02) meets the suite's rest bound on
// kinetic energy (measured 9.6e-8 J/kg). With the plain tolerance the same viscosity left the
// 12,000-particle tank at 7.5e-4 J/kg, five times the bound (docs/design.md), and this column under the
// spiky density at 7.3e-4. The tank at its defaults keeps the plain tolerance.
TEST(Physics, DfsphStepsBelowTheDepthCapTakeATolerancePerFallAndRest) {
  auto ctx = test::makeContext();
  const std::vector<std::string> column = {
      "solver.method=dfsph", "domain.max=[0.1,0.4,0.1]",
      R"(fluid.blocks=[{"shape":"box","min":[0,0,0],"max":[0.1,0.3,0.1]}])", "time.end_frame=49"};
  const std::string path = std::string(SPHFX_SOURCE_DIR) + "/scenes/hydrostatic.json";
  EXPECT_FALSE(sim::dfsphCappedDensityTolerance(loadScene(path, column)).has_value())
      << "the depth cap steps the defaults' column";
  std::vector<std::string> stiff = column;
  stiff.push_back("fluid.artificial_viscosity=0.3");
  const Scene scene = loadScene(path, stiff);
  const double depthStep = 0.4 * scene.fluid.spacing / std::sqrt(-scene.gravity[1] * 0.4);
  const double viscosityStep = 2 / sim::artificialViscosityRate(scene);
  ASSERT_LT(viscosityStep, depthStep);
  const std::optional<double> tolerance = sim::dfsphCappedDensityTolerance(scene);
  ASSERT_TRUE(tolerance.has_value());
  EXPECT_NEAR(*tolerance, 1e-3 * std::pow(viscosityStep / depthStep, 2), 1e-12);
  const double gH = -scene.gravity[1] * scene.fluid.blocks.front().max[1];
  sim::Simulator sim(scene);
  const std::vector<double> kinetic = kineticPerMassToTheEnd(sim, scene);
  const double last = lastQuarterMean(kinetic);
  std::printf(
      "steps of %.3f ms under a cap of %.3f ms: tolerance %.2e, KE/m over the last quarter %.3e J/kg "
      "(bound %.3e)\n",
      1e3 * viscosityStep, 1e3 * depthStep, *tolerance, last, 0.5e-4 * gH);
  EXPECT_LT(last, 0.5e-4 * gH);
}

// DFSPH at its defaults around a collider: a square pillar (box collider) stands through the resting tank
// from below the floor to above the surface, so the fluid meets its four faces, its four convex vertical
// edges and its junction with the floor. The constraint walls hold the collider's samples too (each with
// the share of the sites outside the collider and inside the domain, sim_dfsph_boundary_factor.comp). The
// pillar's lattice is half a cell off the floor's here, so one layer of its samples lies on the floor's
// plane at half weight (sim_boundary_update.comp) and the lattice next to it does not start at rest: the
// first frame's settling may lift the water by up to the suite's energy bound (1 % of g H). From then on,
// over 2 s, the tank never gains energy (bounded by a tenth of the suite's bound), settles under the
// suite's rest bound on kinetic energy, and no particle centre comes within a tenth of a spacing of the
// pillar (measured: +0.147 % of g H in the first frame, -0.023 % after it, 3.1e-6 J/kg, 0.321 s). With
// push walls and the poly6 density the same tank at spacing 0.01 ends at ten times the rest bound
// (docs/validation.md, Known limits), and push walls gain 11.2 % of g H in a closed box in 1 s
// (docs/design.md).
TEST(Physics, DfsphHoldsATankAtRestAroundACollider) {
  auto ctx = test::makeContext();
  const Scene scene =
      test::pillarTank({"solver.method=dfsph", "fluid.spacing=0.02", "time.fps=20", "time.end_frame=41"});
  const double s = scene.fluid.spacing, gH = -scene.gravity[1] * 0.3;
  const Collider& pillar = scene.colliders.front();
  const auto pillarGap = [&](const std::array<float, 3>& p) {  // distance to the box from outside
    double out = 0, in = 1e9;
    for (int a = 0; a < 3; ++a) {
      const double below = pillar.min[a] - p[a], above = p[a] - pillar.max[a];
      out += std::pow(std::max({below, above, 0.0}), 2);
      in = std::min(in, std::max(below, above));  // negative inside: minus the depth
    }
    return out > 0 ? std::sqrt(out) : in;
  };
  sim::Simulator sim(scene);
  const double first = energyAndWallGap(scene, sim.cacheFrame()).first;
  double gain = -1e9, laterGain = -1e9, settled = 0, closest = 1e9;
  std::vector<double> kinetic;
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    const ParticleFrame f = sim.cacheFrame();
    const double energy = energyAndWallGap(scene, f).first;
    gain = std::max(gain, energy - first);
    if (kinetic.empty())
      settled = energy;  // after the first frame
    else
      laterGain = std::max(laterGain, energy - settled);
    double k = 0;
    for (size_t i = 0; i < f.size(); ++i) {
      const auto& v = f.velocity[i];
      k += 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      closest = std::min(closest, pillarGap(f.position[i]));
    }
    kinetic.push_back(k / double(f.size()));
  }
  const size_t tail = std::max<size_t>(1, kinetic.size() / 4);
  const double last = std::accumulate(kinetic.end() - long(tail), kinetic.end(), 0.0) / double(tail);
  std::printf(
      "pillar tank: energy gain %.3f %% of g H (after the first frame %.3f %%), KE/m over the last quarter "
      "%.3e J/kg (bound %.3e), closest approach to the pillar %.3f s\n",
      100 * gain / gH, 100 * laterGain / gH, last, 0.5e-4 * gH, closest / s);
  EXPECT_LE(gain, 0.01 * gH);
  EXPECT_LE(laterGain, 0.001 * gH);
  EXPECT_LT(last, 0.5e-4 * gH);
  EXPECT_GE(closest, 0.1 * s);
}

// solver.dfsph.depth_step_factor: a resting column's motion grows once the step passes about d /
// sqrt(g H) (docs/validation.md), whatever the spacing, so a fixed time.dt_max that holds a shallow tank
// lets a deep one grow. A column 10 spacings wide and 30 deep (H = 0.6 m, d = 0.02 m) at the spiky
// resting configuration with time.dt_max 0.02 (the fall bound then allows 17.5 ms, 2.1 d / sqrt(g H))
// gains energy (85 % of g H on llvmpipe). Capped, it gains none and its fastest particle stays under a
// tenth of the dam-break bound sqrt(2 g H): at 0.8 d / sqrt(g H_domain) (6.1 ms) with the warm share 0.5
// in every substep, and at 0.4 (3.1 ms) with a cold start, what the defaults give a resting column.
struct ColumnRun {
  double gain = 0;     ///< largest rise of (kinetic + potential) energy per mass over frame 2's
  double fastest = 0;  ///< m/s, over every frame
};

ColumnRun runDeepColumn(const std::string& capFactor, const std::string& warmShare) {
  std::vector<std::string> options = {"solver.method=dfsph",
                                      "solver.dfsph.walls=constraints",
                                      "solver.dfsph.density_kernel=spiky",
                                      "solver.dfsph.density_warm_share=" + warmShare,
                                      "solver.dfsph.depth_step_factor=" + capFactor,
                                      "fluid.spacing=0.02",
                                      "domain.max=[0.2,0.7,0.2]",
                                      R"(fluid.blocks=[{"shape":"box","min":[0,0,0],"max":[0.2,0.6,0.2]}])",
                                      "time.dt_max=0.02",
                                      "time.fps=20",
                                      "time.end_frame=11"};
  if (warmShare != "0") options.push_back("solver.dfsph.density_warm_steps=all");  // the cap's steps too
  const Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/hydrostatic.json", options);
  sim::Simulator sim(scene);
  ColumnRun run;
  double first = NAN;
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    const ParticleFrame f = sim.cacheFrame();
    for (const auto& v : f.velocity)
      run.fastest = std::max(run.fastest, double(std::hypot(v[0], v[1], v[2])));
    const double e = energyAndWallGap(scene, f).first;
    if (std::isnan(first)) first = e;
    run.gain = std::max(run.gain, e - first);
  }
  return run;
}

TEST(Physics, DfsphDepthStepHoldsADeepColumn) {
  auto ctx = test::makeContext();
  const double gH = 9.81 * 0.6, bound = std::sqrt(2 * gH);
  const ColumnRun uncapped = runDeepColumn("0", "0.5");
  std::printf("energy gain over 0.5 s uncapped: %.3f %% of g H (fastest %.3f m/s)\n",
              100 * uncapped.gain / gH, uncapped.fastest);
  EXPECT_GT(uncapped.gain, 0.01 * gH) << "the uncapped column does not grow: the test would not test the cap";
  for (const auto& [cap, warm] : {std::pair{"0.8", "0.5"}, std::pair{"0.4", "0"}}) {
    const ColumnRun capped = runDeepColumn(cap, warm);
    std::printf("cap %s, warm share %s: %.3f %% of g H (fastest %.3f m/s)\n", cap, warm,
                100 * capped.gain / gH, capped.fastest);
    EXPECT_LE(capped.gain, 0.001 * gH) << "cap " << cap << ", warm share " << warm;
    EXPECT_LT(capped.fastest, 0.1 * bound) << "cap " << cap << ", warm share " << warm;
  }
}

TEST(Physics, CachedDensityIsThatOfTheCachedPositions) {
  auto ctx = test::makeContext();
  // A dam break in motion (frame 6, ~1.5 m/s): the cached density must be the SPH sum over the cached
  // positions themselves (brute force on the CPU, fluid and wall samples), not over the positions one
  // substep earlier (off by up to ~1 % at the surge front at this spacing).
  const Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json",
                                {"fluid.spacing=0.04", "time.end_frame=6", "cache.attributes=[\"density\"]"});
  sim::Simulator sim(scene);
  while (sim.frame() < scene.time.endFrame) sim.advance();
  const ParticleFrame f = sim.cacheFrame();
  ASSERT_EQ(f.density.size(), f.size());
  const double m = sim::calibratedParticleMass(scene);
  const sim::BoundarySamples walls = sim::sampleBoundaries(scene);
  double worst = 0, speed = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    const auto& x = f.position[i];
    const auto r2 = [&](const auto& y) {
      return std::pow(x[0] - y[0], 2) + std::pow(x[1] - y[1], 2) + std::pow(x[2] - y[2], 2);
    };
    double rho = 0;
    for (const auto& y : f.position) rho += m * sim::densityKernel(scene, r2(y));
    for (const auto& y : walls.rest) rho += y[3] * sim::densityKernel(scene, r2(y));
    worst = std::max(worst, std::fabs(f.density[i] / rho - 1));
    speed = std::max(speed, double(std::hypot(f.velocity[i][0], f.velocity[i][1], f.velocity[i][2])));
  }
  std::printf(
      "cached density against the sum over cached positions: worst relative difference %.2e "
      "(fastest particle %.2f m/s)\n",
      worst, speed);
  EXPECT_GT(speed, 1.0) << "the flow is not moving: the test would not test anything";
  EXPECT_LT(worst, 1e-4);
}

TEST(Physics, DamBreakFrontFollowsMartinMoyce) {
  auto ctx = test::makeContext();
  const auto reference = test::readFrontTable("dam_break_martin_moyce_n2.csv");
  ASSERT_GE(reference.size(), 10u) << "missing studies/reference/dam_break_martin_moyce_n2.csv";
  // CI resolution: a = 0.2 m, spacing a/10 (2000 particles), 60 fps for a finely sampled front.
  const Scene scene = loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json",
                                {"fluid.spacing=0.02", "time.fps=60", "time.end_frame=22"});
  const double a = 0.2, g = 9.81;
  sim::Simulator sim(scene);
  std::vector<std::pair<double, double>> front;  // (T, Z)
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    const ParticleFrame f = sim.cacheFrame();
    // The front: the largest x among particles, less half a spacing (particle centres sit half a
    // spacing inside the fluid's extent).
    float x = 0;
    for (const auto& p : f.position) x = std::max(x, p[0]);
    front.push_back({f.time * std::sqrt(2 * g / a), (x + 0.5 * scene.fluid.spacing) / a});
  }
  double sum = 0, worst = 0;
  int n = 0;
  for (const auto& [T, Z] : reference) {
    if (T > front.back().first) break;
    auto it = std::lower_bound(front.begin(), front.end(), std::make_pair(T, 0.0));
    if (it == front.begin()) continue;
    const auto& [t1, z1] = *it;
    const auto& [t0, z0] = *(it - 1);
    const double zs = z0 + (z1 - z0) * (T - t0) / (t1 - t0);
    sum += std::fabs(zs - Z);
    worst = std::max(worst, std::fabs(zs - Z));
    ++n;
    std::printf("dam break T %.2f: Z simulated %.3f, Martin & Moyce %.2f\n", T, zs, Z);
  }
  ASSERT_GE(n, 8);
  std::printf("dam break front: mean |dZ| %.3f, max %.3f over %d points (T <= %.2f)\n", sum / n, worst, n,
              front.back().first);
  // Tolerance (docs/simulation.md): measured mean 0.088, max 0.144 at this resolution (s = a/10); about
  // twice that leaves room for float-order differences between GL drivers without hiding a regression (the
  // single-layer boundary lagged by 0.35 on average).
  EXPECT_LT(sum / n, 0.15);
  EXPECT_LT(worst, 0.3);
}

// fluid.wall_contact against a lone drop and a tank at rest, for each solver.
class WallContact : public test::SolverTest {};

// The last frame of `scene` run to its end frame, and the largest gain of the energy per unit mass over
// the first frame (J/kg) on the way.
std::pair<ParticleFrame, double> lastFrameAndEnergyGain(const Scene& scene) {
  sim::Simulator sim(scene);
  const double e0 = energyAndWallGap(scene, sim.cacheFrame()).first;
  double growth = -1e9;
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    growth = std::max(growth, energyAndWallGap(scene, sim.cacheFrame()).first - e0);
  }
  return {sim.cacheFrame(), growth};
}

TEST_P(WallContact, ALoneDropRestsHalfASpacingAboveTheFloor) {
  // A particle dropped 0.2 m onto the floor has no neighbours, so its density never rises and nothing
  // but the contact (or the last-resort clamp at 0.05 spacings) stops it. The contact stops its approach
  // where the walls' kernel sum reaches a resting particle's half a spacing from a flat wall: it comes to
  // rest there, and the inelastic stop loses the fall's energy.
  const std::string path = std::string(SPHFX_SOURCE_DIR) + "/studies/scenes/single_particle.json";
  const Scene scene = loadScene(path, {"solver.method=" + GetParam()});
  ASSERT_GT(scene.fluid.wallContact, 0);
  const double s = scene.fluid.spacing, gH = -scene.gravity[1] * 0.21;
  const auto [last, growth] = lastFrameAndEnergyGain(scene);
  ASSERT_EQ(last.size(), 1u);
  const double gap = last.position[0][1] - scene.domain.min[1],
               speed = std::hypot(last.velocity[0][0], last.velocity[0][1], last.velocity[0][2]);
  std::printf("with the contact: %.3f s above the floor at %.3f m/s, energy gain %.2e J/kg\n", gap / s, speed,
              growth);
  EXPECT_NEAR(gap, 0.5 * s, 0.1 * s);
  EXPECT_LT(speed, 0.05);
  EXPECT_LE(growth, 1e-6 * gH);

  // Without it the drop ends at the clamp: the contact, not the density, held it.
  const Scene without = loadScene(path, {"solver.method=" + GetParam(), "fluid.wall_contact=0"});
  const double bare = lastFrameAndEnergyGain(without).first.position[0][1] - scene.domain.min[1];
  std::printf("without: %.3f s above the floor\n", bare / s);
  EXPECT_LT(bare, 0.25 * s);
}

TEST_P(WallContact, ATankAtRestNeverMeetsIt) {
  // Every particle of a resting tank has a full neighbourhood (the surface layer too, with the wall
  // samples beside it), so the contact never acts: the run is bit for bit the run without it.
  const std::string path = std::string(SPHFX_SOURCE_DIR) + "/scenes/hydrostatic.json";
  const std::vector<std::string> set = {"solver.method=" + GetParam(), "fluid.spacing=0.02",
                                        "time.end_frame=13"};
  std::vector<std::string> off = set;
  off.push_back("fluid.wall_contact=0");
  const ParticleFrame with = lastFrameAndEnergyGain(loadScene(path, set)).first;
  const ParticleFrame bare = lastFrameAndEnergyGain(loadScene(path, off)).first;
  ASSERT_EQ(with.size(), bare.size());
  EXPECT_EQ(with.position, bare.position);
  EXPECT_EQ(with.velocity, bare.velocity);
}

// The closest any particle centre comes to a sphere collider's surface over the frames of `scene`, in
// spacings, and the largest gain of the energy per unit mass over the first frame (J/kg).
std::pair<double, double> closestToSphereAndEnergyGain(const Scene& scene, const Vec3d& centre,
                                                       double radius) {
  sim::Simulator sim(scene);
  const double e0 = energyAndWallGap(scene, sim.cacheFrame()).first;
  double closest = 1e30, growth = -1e9;
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    const ParticleFrame f = sim.cacheFrame();
    for (const auto& p : f.position)
      closest = std::min(closest, std::hypot(p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]) - radius);
    growth = std::max(growth, energyAndWallGap(scene, f).first - e0);
  }
  return {closest / scene.fluid.spacing, growth};
}

TEST_P(WallContact, ASplashOverASphereStaysHalfASpacingOffItsSurface) {
  // A block dropped onto a sphere collider spreads over a surface that is convex everywhere, where the
  // walls' kernel sum over a particle is below a flat wall's at the same distance, and the sheet keeps
  // enough neighbours to count as bulk. The contact holds every particle by its distance to the
  // collider: half a spacing, less what one step's linearised approach over the curved surface leaves.
  const std::string json = R"({"domain": {"min": [0,0,0], "max": [0.4,0.5,0.2]},
      "fluid": {"spacing": 0.02, "blocks": [{"min": [0.14,0.26,0.04], "max": [0.26,0.38,0.16]}]},
      "colliders": [{"shape": "sphere", "center": [0.2,0.1,0.1], "radius": 0.08}],
      "time": {"fps": 30, "start_frame": 0, "end_frame": 15}, "solver": {"method": ")" +
                           GetParam() + "\"}}";
  const Vec3d centre{0.2, 0.1, 0.1};
  Scene scene = test::sceneFromJson(json);
  ASSERT_GT(scene.fluid.wallContact, 0);
  const double gH = -scene.gravity[1] * 0.38;
  const auto [closest, growth] = closestToSphereAndEnergyGain(scene, centre, 0.08);
  std::printf("with the contact: closest %.3f spacings from the sphere, energy gain %.2e J/kg\n", closest,
              growth);
  EXPECT_GT(closest, 0.4);
  EXPECT_LE(growth, 1e-6 * gH);

  // Without it the splash reaches the last-resort clamp (0.05 spacings) somewhere on the sphere.
  scene.fluid.wallContact = 0;
  const double bare = closestToSphereAndEnergyGain(scene, centre, 0.08).first;
  std::printf("without: closest %.3f spacings\n", bare);
  EXPECT_LT(bare, 0.25);
}

INSTANTIATE_TEST_SUITE_P(Solvers, WallContact, ::testing::Values("wcsph", "dfsph"), test::solverParamName);

}  // namespace
