// Overrides for every run of the stability suite (`sphfx stability --set`) and of a study (`sphfx study
// --set`): applied after each case's own and before the run's solver or grid point, seen by the reports'
// digests, left out of the runs whose settings do not read them, and a bad one (or one that no run reads)
// is an error naming the case (and the solver) before any run.
#include <gtest/gtest.h>

#include "sphfx/core/error.h"
#include "sphfx/study/stability.h"
#include "sphfx/study/study.h"

using namespace sphfx;
using namespace sphfx::study;

namespace {

StabilitySuite shippedSuite() {
  return loadStabilitySuite(std::string(SPHFX_SOURCE_DIR) + "/studies/stability.json");
}

/// The case called `name` of a suite's or study's cases.
template <class Case>
const Case& caseNamed(const std::vector<Case>& cases, const std::string& name) {
  for (const Case& c : cases)
    if (c.name == name) return c;
  throw std::runtime_error("no case " + name);
}

StudySpec quickStudy() {
  return loadStudy(std::string(SPHFX_SOURCE_DIR) + "/studies/quick.json");
}

/// The case's grid point whose `path` axis takes `value`.
GridPoint pointWith(const StudyCase& c, const std::string& path, const Json& value) {
  for (const GridPoint& p : gridPoints(c))
    for (const auto& [axis, v] : p)
      if (axis == path && v == value) return p;
  throw std::runtime_error("no grid point with " + path);
}

}  // namespace

TEST(StabilitySuite, OverridesFollowTheCaseAndPrecedeTheSolver) {
  StabilitySuite suite = shippedSuite();
  const StabilityCase& stiff = caseNamed(suite.cases, "stiff_tait_c100");  // its own set: speed of sound 200
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

// A setting judged with the suite before it becomes a default may mean nothing to some cases:
// fluid.wall_drag to a case without viscosity. It is left out there; one that no run reads stops the suite.
TEST(StabilitySuite, AnOverrideACaseDoesNotReadIsLeftOutThere) {
  StabilitySuite suite = shippedSuite();
  suite.overrides = {"fluid.wall_drag=friction"};
  std::vector<std::string> dropped;
  const Scene inviscid =
      resolveStabilityScene(suite, caseNamed(suite.cases, "zero_viscosity"), "wcsph", 0, &dropped);
  EXPECT_EQ(inviscid.fluid.viscosityModel, ViscosityModel::None);
  EXPECT_EQ(dropped, suite.overrides);
  dropped.clear();
  const Scene resting = resolveStabilityScene(suite, caseNamed(suite.cases, "resting"), "dfsph", 0, &dropped);
  EXPECT_EQ(resting.fluid.wallDrag, WallDrag::Friction);
  EXPECT_TRUE(dropped.empty());
  suite.overrides = {"fluid.wall_friction=0.01"};  // read with wall_drag friction alone
  try {
    runStabilitySuite(suite, true, "unused", StudyOptions{});
    FAIL() << "an override that no run reads ran";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--set fluid.wall_friction=0.01: no run of the suite reads it"),
              std::string::npos)
        << e.what();
  }
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

TEST(StudyOverrides, FollowTheCaseAndPrecedeTheGridPoint) {
  StudySpec spec = quickStudy();
  const StudyCase& c = caseNamed(spec.cases, "dam_break_sound_speed");  // its own set: spacing 0.01
  const GridPoint point = gridPoints(c).front();
  EXPECT_DOUBLE_EQ(resolveRunScene(spec, c, point).fluid.spacing, 0.01);
  spec.overrides = {"fluid.spacing=0.02"};
  EXPECT_DOUBLE_EQ(resolveRunScene(spec, c, point).fluid.spacing, 0.02) << "the study's after the case's";
  spec.overrides = {"solver.dfsph.jacobi_momentum=0.7"};
  const StudyCase& dam = caseNamed(spec.cases, "dam_break");  // solver.method is an axis
  EXPECT_DOUBLE_EQ(
      resolveRunScene(spec, dam, pointWith(dam, "solver.method", "dfsph")).solver.dfsph.jacobiMomentum, 0.7);
  EXPECT_EQ(resolveRunScene(spec, dam, pointWith(dam, "solver.method", "wcsph")).solver.method,
            Solver::WCSPH);
}

// As the suite's: an override that a run's settings leave unread is left out of that run (the quick
// study's Poiseuille case has the laplacian viscosity, which reads no fluid.wall_drag).
TEST(StudyOverrides, AnOverrideARunDoesNotReadIsLeftOutThere) {
  StudySpec spec = quickStudy();
  spec.overrides = {"fluid.wall_drag=friction"};
  const StudyCase& poiseuille = caseNamed(spec.cases, "poiseuille");
  std::vector<std::string> dropped;
  const Scene laplacian = resolveRunScene(spec, poiseuille, gridPoints(poiseuille).front(), &dropped);
  EXPECT_EQ(laplacian.fluid.viscosityModel, ViscosityModel::Laplacian);
  EXPECT_EQ(dropped, spec.overrides);
  dropped.clear();
  const StudyCase& dam = caseNamed(spec.cases, "dam_break");
  EXPECT_EQ(resolveRunScene(spec, dam, gridPoints(dam).front(), &dropped).fluid.wallDrag, WallDrag::Friction);
  EXPECT_TRUE(dropped.empty());
  spec.overrides = {"fluid.wall_friction=0.01"};  // read with wall_drag friction alone
  try {
    runStudy(spec, "unused", StudyOptions{});
    FAIL() << "an override that no run reads ran";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--set fluid.wall_friction=0.01: no run of the study reads it"),
              std::string::npos)
        << e.what();
  }
}

TEST(StudyOverrides, AnAxisIsNotOverridden) {
  StudySpec spec = quickStudy();
  spec.overrides = {"fluid.spacing=0.02"};
  const StudyCase& dam = caseNamed(spec.cases, "dam_break");  // fluid.spacing is an axis
  try {
    resolveRunScene(spec, dam, gridPoints(dam).front());
    FAIL() << "an override of an axis resolved";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("fluid.spacing is an axis of study case dam_break"),
              std::string::npos)
        << e.what();
  }
}

TEST(StudyOverrides, TheDigestSeesAnOverride) {
  StudySpec spec = quickStudy();
  const std::string before = studyInputsDigest(spec);
  spec.overrides = {"solver.dfsph.jacobi_momentum=0.7"};
  EXPECT_NE(studyInputsDigest(spec), before);
}
