// Kernels integrate to one, gradients sum to zero, and the calibrated mass puts the lattice at rest
// density: checked by numerical quadrature, independent of the GPU code.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "boundary_akinci2012.h"
#include "dfsph_solver.h"
#include "gpu_types.h"
#include "sim_test_util.h"
#include "sphfx/core/scene.h"

using namespace sphfx;

namespace {
// Midpoint quadrature over the cube [-h, h]^3 with n^3 cells.
template <class F>
double integrate(double h, int n, F f) {
  const double d = 2 * h / n;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) sum += f(-h + (i + 0.5) * d, -h + (j + 0.5) * d, -h + (k + 0.5) * d);
  return sum * d * d * d;
}
// The density kernel a scene's solver sums with, written out here from the factors (which the
// integration tests below check): Wendland C2 for WCSPH at its default, poly6 otherwise.
double densityW(const Scene& scene, double r2) {
  const double h = scene.kernelRadius();
  if (r2 >= h * h) return 0;
  if (scene.solver.method == Solver::WCSPH && scene.solver.wcsph.kernel == SphKernel::WendlandC2) {
    const double q = std::sqrt(r2) / h;
    return sim::wendlandFactors(h).density * std::pow(1 - q, 4) * (1 + 4 * q);
  }
  return sim::kernelFactors(h).poly6 * std::pow(h * h - r2, 3);
}

// The scene with each density kernel: WCSPH's Wendland C2, WCSPH's Mueller pair, DFSPH's poly6.
std::vector<Scene> withEachKernel(const Scene& base) {
  std::vector<Scene> scenes(3, base);
  scenes[0].solver.method = Solver::WCSPH;
  scenes[0].solver.wcsph.kernel = SphKernel::WendlandC2;
  scenes[1].solver.method = Solver::WCSPH;
  scenes[1].solver.wcsph.kernel = SphKernel::Muller2003;
  scenes[2].solver.method = Solver::DFSPH;
  return scenes;
}
}  // namespace

TEST(Kernels, Poly6AndSpikyIntegrateToOne) {
  for (double h : {0.02, 0.1, 1.0}) {
    const sim::KernelFactors k = sim::kernelFactors(h);
    const double poly6 = integrate(h, 120, [&](double x, double y, double z) {
      const double r2 = x * x + y * y + z * z;
      return r2 < h * h ? k.poly6 * std::pow(h * h - r2, 3) : 0.0;
    });
    // Spiky W = c (h - r)^3 with grad W = -3 c (h - r)^2 r/|r|: c = -spikyGradient / 3.
    const double spiky = integrate(h, 120, [&](double x, double y, double z) {
      const double r = std::sqrt(x * x + y * y + z * z);
      return r < h ? -k.spikyGradient / 3 * std::pow(h - r, 3) : 0.0;
    });
    EXPECT_NEAR(poly6, 1.0, 2e-3) << h;
    EXPECT_NEAR(spiky, 1.0, 5e-3) << h;
  }
}

TEST(Kernels, SpikyGradientsSumToZeroOnSymmetricNeighbourhood) {
  const double h = 0.04, s = 0.02;
  const sim::KernelFactors k = sim::kernelFactors(h);
  double g[3] = {0, 0, 0}, mag = 0;
  // A particle off the lattice (x0) sees an asymmetric set; one on the lattice sees a symmetric one.
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int l = -3; l <= 3; ++l) {
        const double r[3] = {i * s, j * s, l * s};
        const double len = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        if (len <= 0 || len >= h) continue;
        for (int a = 0; a < 3; ++a) g[a] += k.spikyGradient * (h - len) * (h - len) / len * r[a];
        mag += std::fabs(k.spikyGradient) * (h - len) * (h - len);
      }
  for (int a = 0; a < 3; ++a) EXPECT_LT(std::fabs(g[a]), 1e-9 * mag);
}

TEST(Kernels, CalibratedMassPutsLatticeAtRestDensity) {
  for (const Scene& scene : withEachKernel(test::sceneFromJson(
           R"({"fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.2,0.2,0.2]}]}})"))) {
    const double m = sim::calibratedParticleMass(scene), s = 0.02;
    double rho = 0;
    for (int i = -4; i <= 4; ++i)
      for (int j = -4; j <= 4; ++j)
        for (int l = -4; l <= 4; ++l) rho += m * densityW(scene, s * s * (i * i + j * j + l * l));
    EXPECT_NEAR(rho, 1000.0, 1e-6);
    // Within a few percent of the nominal rho0 s^3: the calibration is a correction, not a new model.
    EXPECT_NEAR(m / scene.particleMass(), 1.0, 0.1);
  }
}

// The boundary samples complete the neighbourhood of the initial lattice: every seeded particle, in the
// middle, at a wall, at an edge or in a corner of the domain, and next to a box collider, starts at rest
// density (fluid + boundary sum on the CPU, brute force).
TEST(Kernels, BoundarySamplesPutWallParticlesAtRestDensity) {
  for (const Scene& scene : withEachKernel(test::sceneFromJson(
           R"({"domain": {"min": [0,0,0], "max": [0.2,0.24,0.16]}, "fluid": {"spacing": 0.02,
      "blocks": [{"min": [0,0,0], "max": [0.2,0.16,0.16]}]}, "colliders": [{"name": "b", "shape": "box",
      "min": [0.08,0.16,0.04], "max": [0.16,0.24,0.12]}]})"))) {
    const double m = sim::calibratedParticleMass(scene), h = scene.kernelRadius();
    auto W = [&](const std::array<float, 3>& a, const std::array<float, 4>& b) {
      return densityW(scene, std::pow(a[0] - b[0], 2) + std::pow(a[1] - b[1], 2) + std::pow(a[2] - b[2], 2));
    };
    const SeededParticles seeds = seedParticles(scene);
    const sim::BoundarySamples b = sim::sampleBoundaries(scene);
    EXPECT_EQ(sim::boundaryLayers(scene), 2);
    // Particles of the top layers (y > fill - h, beside the collider's sides excepted) lack neighbours
    // above: the free surface. Every other particle's support is filled by fluid and samples.
    double worst = 0;
    int touching = 0, checked = 0;
    for (const auto& x : seeds.position) {
      if (x[1] > 0.16 - h) continue;
      double rho = 0, wall = 0;
      for (const auto& y : seeds.position) rho += m * W(x, {y[0], y[1], y[2], 0});
      for (const auto& y : b.rest) wall += y[3] * W(x, y);
      touching += wall > 0;
      ++checked;
      worst = std::max(worst, std::fabs((rho + wall) / 1000.0 - 1.0));
    }
    std::printf(
        "boundary: %zu samples; %d of %d particles below the surface see them; worst density error "
        "%.2e\n",
        b.size(), touching, checked, worst);
    EXPECT_GT(touching, checked / 2);
    EXPECT_LT(worst, 1e-5);
  }
}

TEST(Kernels, WendlandC2IntegratesToOneAndItsGradientIsItsDerivative) {
  for (double h : {0.02, 0.1, 1.0}) {
    const sim::WendlandFactors w = sim::wendlandFactors(h);
    const auto W = [&](double r) {
      const double q = r / h;
      return q < 1 ? w.density * std::pow(1 - q, 4) * (1 + 4 * q) : 0.0;
    };
    const double total =
        integrate(h, 120, [&](double x, double y, double z) { return W(std::sqrt(x * x + y * y + z * z)); });
    EXPECT_NEAR(total, 1.0, 2e-3) << h;
    // The shader's gradient, gradient (1 - q)^3 r, against a central difference of W along r.
    for (double q : {0.1, 0.35, 0.6, 0.9}) {
      const double r = q * h, e = 1e-6 * h;
      const double numeric = (W(r + e) - W(r - e)) / (2 * e);
      const double analytic = w.gradient * std::pow(1 - q, 3) * r;
      EXPECT_NEAR(analytic, numeric, 1e-6 * std::fabs(numeric)) << h << " " << q;
    }
  }
}

TEST(Kernels, CalibratedMassFollowsTheSolversDensityKernel) {
  // WCSPH's default Wendland C2 and DFSPH's poly6 sum differently over the lattice at h = 2 s; each mass
  // stays within a few percent of the nominal rho0 s^3, and they differ.
  double masses[2] = {0, 0};
  int k = 0;
  for (Solver method : {Solver::WCSPH, Solver::DFSPH}) {
    Scene scene = test::sceneFromJson(R"({"fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0],
                                          "max": [0.2,0.2,0.2]}]}})");
    scene.solver.method = method;
    EXPECT_EQ(sim::usesWendland(scene), method == Solver::WCSPH);
    const double s = scene.fluid.spacing, nominal = scene.fluid.restDensity * s * s * s;
    masses[k] = sim::calibratedParticleMass(scene);
    EXPECT_NEAR(masses[k++], nominal, 0.1 * nominal);
  }
  EXPECT_GT(std::fabs(masses[0] - masses[1]), 1e-3 * masses[0]);
}

// sim::artificialViscosityRate() against a brute-force spectral radius: the linearised artificial term,
// a_i = -sum_j m nu F(r) / (r^2 + 0.01 h^2) (x_ij x_ij^T)(v_i - v_j), applied as an operator to a velocity
// field on an 8^3 periodic lattice (its gradient F = -W'(r) / r taken here by central differences of the
// kernel), and its largest eigenvalue found by power iteration from a random field. The periodic lattice
// holds the modes k = pi / s (a, b, c) / 4, a subset of the function's grid, so its rate is at most the
// function's; both must agree within 1 %. The step cap is 2 / rate where it binds.
TEST(Kernels, ArtificialViscosityRateIsTheLinearisedTermsSpectralRadius) {
  struct Case {
    const char* solver;  // the scene's "solver" object
    bool wendland;       // its gradient kernel is Wendland C2 (else spiky)
  };
  for (const Case& c : {Case{R"({"method": "dfsph", "dfsph": {"density_kernel": "spiky"}})", false},
                        Case{R"({"method": "dfsph"})", true}, Case{R"({"method": "wcsph"})", true}}) {
    const Scene scene =
        test::sceneFromJson(std::string(R"({"fluid": {"spacing": 0.01, "artificial_viscosity": 0.3,
        "blocks": [{"min": [0,0,0], "max": [0.2,0.2,0.2]}]}, "solver": )") +
                            c.solver + "}");
    const double s = scene.fluid.spacing, h = scene.kernelRadius();
    const bool wendland = c.wendland;
    double mass = sim::calibratedParticleMass(scene);
    if (scene.solver.method == Solver::DFSPH)
      mass *=
          sim::DFSPHSolver::densityMassScale(scene.solver.dfsph.densityKernel, scene.solver.kernelSupport);
    const double nu = scene.fluid.artificialViscosity * h * scene.soundSpeed() / scene.fluid.restDensity;
    auto kernel = [&](double r) { return wendland ? sim::wendlandKernel(h, r) : sim::spikyKernel(h, r); };
    auto weight = [&](double r) {
      const double e = 1e-6 * h, slope = (kernel(r + e) - kernel(r - e)) / (2 * e);
      return mass * nu * (-slope / r) / (r * r + 0.01 * h * h);
    };
    constexpr int P = 8, n = 2;                  // lattice cells per axis; offsets within h = 2 s
    std::vector<std::array<double, 4>> offsets;  // x, y, z, weight
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j)
        for (int l = -n; l <= n; ++l) {
          const double r = s * std::sqrt(double(i * i + j * j + l * l));
          if (r > 0 && r < h) offsets.push_back({double(i), double(j), double(l), weight(r)});
        }
    auto site = [](int i, int j, int l) { return size_t(((i + P) % P * P + (j + P) % P) * P + (l + P) % P); };
    std::vector<std::array<double, 3>> v(P * P * P), av(v.size());
    std::srand(7);
    for (auto& x : v)
      for (double& c3 : x) c3 = double(std::rand()) / RAND_MAX - 0.5;
    double rate = 0;
    for (int iteration = 0; iteration < 400; ++iteration) {
      for (int i = 0; i < P; ++i)
        for (int j = 0; j < P; ++j)
          for (int l = 0; l < P; ++l) {
            const size_t a = site(i, j, l);
            std::array<double, 3> sum{};
            for (const auto& o : offsets) {
              const size_t b = site(i + int(o[0]), j + int(o[1]), l + int(o[2]));
              const double x[3] = {o[0] * s, o[1] * s, o[2] * s};
              double dot = 0;
              for (int k = 0; k < 3; ++k) dot += x[k] * (v[a][size_t(k)] - v[b][size_t(k)]);
              for (int k = 0; k < 3; ++k) sum[size_t(k)] += o[3] * dot * x[k];
            }
            av[a] = sum;
          }
      double norm2 = 0, dot = 0;
      for (size_t a = 0; a < v.size(); ++a)
        for (size_t k = 0; k < 3; ++k) {
          norm2 += av[a][k] * av[a][k];
          dot += av[a][k] * v[a][k];
        }
      double vnorm2 = 0;
      for (const auto& x : v)
        for (double c3 : x) vnorm2 += c3 * c3;
      rate = dot / vnorm2;  // the Rayleigh quotient
      for (size_t a = 0; a < v.size(); ++a)
        for (size_t k = 0; k < 3; ++k) v[a][k] = av[a][k] / std::sqrt(norm2);
    }
    const double computed = sim::artificialViscosityRate(scene);
    std::printf("solver %s: rate %.1f 1/s (brute force %.1f 1/s)\n", c.solver, computed, rate);
    EXPECT_GE(computed, rate * (1 - 1e-6));
    EXPECT_NEAR(computed, rate, 0.01 * rate);
    const sim::SimParams p = sim::makeSimParams(scene, 1, 0, 1);
    EXPECT_LE(p.limits[1], float(2 / computed));
  }
  Scene laplacian = test::sceneFromJson(R"({"fluid": {"viscosity_model": "laplacian", "viscosity": 1e-6,
      "blocks": [{"min": [0,0,0], "max": [0.2,0.2,0.2]}]}})");
  EXPECT_EQ(sim::artificialViscosityRate(laplacian), 0.0);
}
