// The stability suite's overrides for every run (`sphfx stability --set`): applied after each case's own
// and before the run's solver, seen by the reports' digest, and a bad one is an error naming the case
// and the solver.
#include <gtest/gtest.h>

#include "sphfx/core/error.h"
#include "sphfx/study/stability.h"

using namespace sphfx;
using namespace sphfx::study;

namespace {

StabilitySuite shippedSuite() {
  return loadStabilitySuite(std::string(SPHFX_SOURCE_DIR) + "/studies/stability.json");
}

const StabilityCase& caseNamed(const StabilitySuite& suite, const std::string& name) {
  for (const auto& c : suite.cases)
    if (c.name == name) return c;
  throw std::runtime_error("no case " + name);
}

}  // namespace

TEST(StabilitySuite, OverridesFollowTheCaseAndPrecedeTheSolver) {
  StabilitySuite suite = shippedSuite();
  const StabilityCase& stiff = caseNamed(suite, "stiff_tait_c100");  // its own set: speed of sound 200
  EXPECT_DOUBLE_EQ(resolveStabilityScene(suite, stiff, "wcsph", 0).solver.speedOfSound, 200);
  suite.overrides = {"solver.speed_of_sound=50", "solver.method=dfsph"};
  const Scene scene = resolveStabilityScene(suite, stiff, "wcsph", 0);
  EXPECT_DOUBLE_EQ(scene.solver.speedOfSound, 50) << "the suite's override after the case's";
  EXPECT_EQ(scene.solver.method, Solver::WCSPH) << "the run's solver after the overrides";
}

TEST(StabilitySuite, TheDigestSeesAnOverride) {
  StabilitySuite suite = shippedSuite();
  const std::string before = stabilityInputsDigest(suite, true);
  suite.overrides = {"fluid.rest_density=999"};
  EXPECT_NE(stabilityInputsDigest(suite, true), before);
}

TEST(StabilitySuite, ASolverParameterReachesThatSolversRuns) {
  StabilitySuite suite = shippedSuite();
  suite.overrides = {"solver.dfsph.jacobi_momentum=0.7"};
  const StabilityCase& first = suite.cases.front();
  EXPECT_DOUBLE_EQ(resolveStabilityScene(suite, first, "dfsph", 0).solver.dfsph.jacobiMomentum, 0.7);
  // The run's solver drops the other solver's group, as `sphfx simulate --set solver.method=...` does.
  EXPECT_EQ(resolveStabilityScene(suite, first, "wcsph", 0).solver.method, Solver::WCSPH);
}

TEST(StabilitySuite, ABadOverrideNamesTheCaseAndSolver) {
  StabilitySuite suite = shippedSuite();
  suite.overrides = {"fluid.no_such_parameter=1"};
  const StabilityCase& first = suite.cases.front();
  try {
    resolveStabilityScene(suite, first, "wcsph", 0);
    FAIL() << "an unknown parameter resolved";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("(stability case " + first.name + ", wcsph)"), std::string::npos) << what;
    EXPECT_NE(what.find("/fluid/no_such_parameter"), std::string::npos) << what;
  }
}
