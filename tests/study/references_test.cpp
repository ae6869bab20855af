// The reference solutions checked against independent facts: the published tables load as published,
// and the Poiseuille series satisfies its PDE, initial and boundary conditions and steady limit.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "references.h"
#include "sphfx/core/error.h"
#include "sphfx/core/scene.h"

using namespace sphfx::study;

TEST(References, MartinMoyceTablesLoad) {
  const MartinMoyce mm = MartinMoyce::load(std::string(SPHFX_SOURCE_DIR) + "/studies/reference");
  EXPECT_EQ(mm.front.x().size(), 15u);
  EXPECT_DOUBLE_EQ(mm.front.at(0.41), 1.11);
  EXPECT_DOUBLE_EQ(mm.front.at(3.33), 4.11);
  EXPECT_NEAR(mm.front.at((1.19 + 1.43) / 2), (1.44 + 1.67) / 2, 1e-12);  // linear between samples
  EXPECT_DOUBLE_EQ(mm.height.at(0.56), 0.94);
  EXPECT_THROW(mm.front.at(5.0), std::out_of_range);
}

TEST(References, HydrostaticPressure) {
  EXPECT_DOUBLE_EQ(hydrostaticPressure(1000, 9.81, 0.3, 0.1), 1000 * 9.81 * 0.2);
  EXPECT_DOUBLE_EQ(hydrostaticPressure(1000, 9.81, 0.3, 0.4), 0.0);
}

TEST(References, PoiseuilleStartsAtRestAndReachesTheParabola) {
  const double L = 1e-3, F = 1e-4, nu = 1e-6;
  for (double y : {0.1e-3, 0.5e-3, 0.9e-3}) {
    EXPECT_NEAR(poiseuilleVelocity(y, 0, L, F, nu), 0, 1e-9 * F * L * L / nu);
    EXPECT_NEAR(poiseuilleVelocity(y, 100, L, F, nu), F / (2 * nu) * y * (L - y), 1e-12);
  }
  EXPECT_NEAR(poiseuilleVelocity(L / 2, 100, L, F, nu), F * L * L / (8 * nu), 1e-12);  // 1.25e-5 m/s (Morris)
  EXPECT_NEAR(poiseuilleVelocity(0, 0.1, L, F, nu), 0, 1e-15);  // no slip at the plates
}

TEST(References, PoiseuilleSatisfiesTheDiffusionEquation) {
  // dv/dt = nu d2v/dy2 + F, checked by central differences at an interior point and a mid-transient time.
  const double L = 1e-3, F = 1e-4, nu = 1e-6, y = 0.3e-3, t = 0.05;
  const double dt = 1e-5, dy = 1e-6;
  const double dvdt =
      (poiseuilleVelocity(y, t + dt, L, F, nu) - poiseuilleVelocity(y, t - dt, L, F, nu)) / (2 * dt);
  const double d2v = (poiseuilleVelocity(y + dy, t, L, F, nu) - 2 * poiseuilleVelocity(y, t, L, F, nu) +
                      poiseuilleVelocity(y - dy, t, L, F, nu)) /
                     (dy * dy);
  EXPECT_NEAR(dvdt, nu * d2v + F, 1e-3 * F);
}

TEST(References, MalformedTableIsAnInputError) {
  EXPECT_THROW(Table({1, 2}, {1}), sphfx::InputError);
  EXPECT_THROW(Table({2, 1}, {1, 1}), sphfx::InputError);
  EXPECT_THROW(Table::readCsv("/nonexistent.csv"), sphfx::IoError);
}

TEST(References, TaylorGreenDecaysAtNuK2AndTheSeededFieldIsItsMode) {
  const double U0 = 0.01, nu = 1e-3, L = 0.1;
  EXPECT_DOUBLE_EQ(taylorGreenAmplitude(U0, 0, L, L, nu), U0);
  EXPECT_NEAR(taylorGreenAmplitude(U0, L * L / (8 * M_PI * M_PI * nu), L, L, nu), U0 / M_E, 1e-15);
  // The seeded field (scene.h, taylorGreenVelocity) in an Lx != Lz box: divergence-free, and
  // lap u = -(kx^2 + kz^2) u, so the viscous term decays it at the reference's rate.
  sphfx::Domain d;
  d.min = {-0.05, 0, 0.02};
  d.max = {0.15, 0.06, 0.12};
  const double lx = 0.2, lz = 0.1, k2 = 4 * M_PI * M_PI * (1 / (lx * lx) + 1 / (lz * lz)), e = 1e-5;
  auto v = [&](double x, double z) { return sphfx::taylorGreenVelocity(d, U0, {x, 0.03, z}); };
  for (const auto& [x, z] : {std::pair{0.013, 0.047}, std::pair{0.1, 0.09}}) {
    const double div = (v(x + e, z)[0] - v(x - e, z)[0] + v(x, z + e)[2] - v(x, z - e)[2]) / (2 * e);
    EXPECT_NEAR(div, 0, 1e-6 * U0 / e);
    for (int a : {0, 2}) {
      const double lap =
          (v(x + e, z)[a] + v(x - e, z)[a] + v(x, z + e)[a] + v(x, z - e)[a] - 4 * v(x, z)[a]) / (e * e);
      EXPECT_NEAR(lap, -k2 * v(x, z)[a], 1e-3 * k2 * U0) << a;
    }
    EXPECT_EQ(v(x, z)[1], 0);
  }
}
