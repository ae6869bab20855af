// Kernels integrate to one, gradients sum to zero, and the calibrated mass puts the lattice at rest
// density: checked by numerical quadrature, independent of the GPU code.
#include <gtest/gtest.h>

#include <cmath>

#include "boundary_akinci2012.h"
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
