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
  const Scene scene = test::sceneFromJson(
      R"({"fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.2,0.2,0.2]}]}})");
  const double m = sim::calibratedParticleMass(scene), s = 0.02, h = scene.kernelRadius();
  const sim::KernelFactors k = sim::kernelFactors(h);
  double rho = 0;
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j)
      for (int l = -4; l <= 4; ++l) {
        const double r2 = s * s * (i * i + j * j + l * l);
        if (r2 < h * h) rho += m * k.poly6 * std::pow(h * h - r2, 3);
      }
  EXPECT_NEAR(rho, 1000.0, 1e-6);
  // Within a few percent of the nominal rho0 s^3: the calibration is a correction, not a new model.
  EXPECT_NEAR(m / scene.particleMass(), 1.0, 0.1);
}

// The boundary samples complete the neighbourhood of the initial lattice: every seeded particle, in the
// middle, at a wall, at an edge or in a corner of the domain, and next to a box collider, starts at rest
// density (fluid + boundary sum on the CPU, brute force).
TEST(Kernels, BoundarySamplesPutWallParticlesAtRestDensity) {
  const Scene scene = test::sceneFromJson(
      R"({"domain": {"min": [0,0,0], "max": [0.2,0.24,0.16]}, "fluid": {"spacing": 0.02,
      "blocks": [{"min": [0,0,0], "max": [0.2,0.16,0.16]}]}, "colliders": [{"name": "b", "shape": "box",
      "min": [0.08,0.16,0.04], "max": [0.16,0.24,0.12]}]})");
  const double m = sim::calibratedParticleMass(scene), h = scene.kernelRadius();
  const sim::KernelFactors k = sim::kernelFactors(h);
  auto W = [&](const std::array<float, 3>& a, const std::array<float, 4>& b) {
    const double r2 = std::pow(a[0] - b[0], 2) + std::pow(a[1] - b[1], 2) + std::pow(a[2] - b[2], 2);
    return r2 < h * h ? k.poly6 * std::pow(h * h - r2, 3) : 0.0;
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
