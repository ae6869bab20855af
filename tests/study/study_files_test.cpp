// The committed study files: studies/full.json (the complete grid of issue 6, not run in CI) and
// studies/quick.json load with the study loader, and every run's scene resolves to a valid scene, so a
// long study cannot stop hours in on a bad grid point.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <string>

#include "sphfx/core/error.h"
#include "sphfx/core/scene.h"
#include "sphfx/study/study.h"

using namespace sphfx;
using namespace sphfx::study;

namespace {

const std::string kStudies = std::string(SPHFX_SOURCE_DIR) + "/studies/";

struct Census {
  size_t runs = 0;
  std::map<std::pair<Validation, Solver>, size_t> runsBySolver;
  std::map<std::string, std::set<double>> spacingsByCase;
  std::set<std::string> stepControls;  // "cfl" / "fixed", per solver
  bool soundSpeedVaries = false;
};

Census census(const std::string& file) {
  const StudySpec spec = loadStudy(kStudies + file);
  Census c;
  for (const StudyCase& sc : spec.cases) {
    std::map<std::string, std::set<std::string>> values;
    for (const GridPoint& point : gridPoints(sc)) {
      const Scene scene = resolveRunScene(spec, sc, point);  // throws on an invalid run
      ++c.runs;
      ++c.runsBySolver[{sc.validation, scene.solver.method}];
      c.spacingsByCase[sc.name].insert(scene.fluid.spacing);
      c.stepControls.insert(std::string(scene.solver.method == Solver::WCSPH ? "wcsph " : "dfsph ") +
                            (scene.time.mode == TimeStepMode::Cfl ? "cfl" : "fixed"));
      if (scene.solver.method == Solver::WCSPH) values["c"].insert(std::to_string(scene.solver.speedOfSound));
      if (sc.validation == Validation::TaylorGreen) {
        for (int a = 0; a < 3; ++a) EXPECT_TRUE(scene.domain.isPeriodic(a)) << sc.name;
        EXPECT_EQ(scene.fluid.viscosityModel, ViscosityModel::Laplacian) << sc.name;
      }
      if (sc.validation == Validation::Poiseuille) {
        EXPECT_TRUE(scene.domain.isPeriodic(0)) << sc.name;
        EXPECT_EQ(scene.fluid.viscosityModel, ViscosityModel::Laplacian) << sc.name;
      }
    }
    c.soundSpeedVaries = c.soundSpeedVaries || values["c"].size() >= 3;
    if (!sc.convergenceAxis.empty()) {
      EXPECT_EQ(sc.convergenceAxis, "fluid.spacing") << sc.name;
    }
  }
  return c;
}

TEST(StudyFiles, FullGridCoversSolversSpacingsStepControlAndSoundSpeed) {
  const Census c = census("full.json");
  std::printf("studies/full.json: %zu runs\n", c.runs);
  // Every case with a reference, for both solvers.
  for (Validation v :
       {Validation::DamBreak, Validation::Hydrostatic, Validation::Poiseuille, Validation::TaylorGreen})
    for (Solver solver : {Solver::WCSPH, Solver::DFSPH})
      EXPECT_GT(c.runsBySolver.count({v, solver}), 0u) << int(v) << " " << int(solver);
  for (const auto& [name, spacings] : c.spacingsByCase) EXPECT_GE(spacings.size(), 3u) << name;
  EXPECT_EQ(c.stepControls, (std::set<std::string>{"wcsph cfl", "wcsph fixed", "dfsph cfl", "dfsph fixed"}));
  EXPECT_TRUE(c.soundSpeedVaries);
  size_t sum = 0;
  for (const auto& [key, n] : c.runsBySolver) sum += n;
  EXPECT_EQ(sum, c.runs);
  EXPECT_GT(c.runs, census("quick.json").runs);
}

TEST(StudyFiles, QuickStudyHasPoiseuilleAtThreeOrMoreSpacings) {
  const Census c = census("quick.json");
  std::printf("studies/quick.json: %zu runs\n", c.runs);
  EXPECT_GT(c.runsBySolver.count({Validation::Poiseuille, Solver::WCSPH}), 0u);
  EXPECT_GT(c.runsBySolver.count({Validation::Poiseuille, Solver::DFSPH}), 0u);
  for (const auto& [name, spacings] : c.spacingsByCase) {
    if (name.find("poiseuille") != std::string::npos) {
      EXPECT_GE(spacings.size(), 3u) << name;
    }
  }
}

}  // namespace

// A case's ranking error is one its validation measures; front_self (the distance from the case's finest
// run) needs the axis along which the finest run is found.
TEST(StudyFiles, ACaseRanksByAnErrorItsValidationMeasures) {
  const std::string path = testing::TempDir() + "metric_study.json";
  auto loadWith = [&](const std::string& extra) {
    std::ofstream(path)
        << R"({"cases": [{"name": "d", "scene": "scenes/dam_break.json", "validation": "dam_break",
      "axes": [{"path": "fluid.spacing", "values": [0.02, 0.01]}])"
        << extra << "}]}";
    return loadStudy(path);
  };
  EXPECT_EQ(loadWith(R"(, "convergence_axis": "fluid.spacing", "metric": "front_self")").cases[0].metric,
            "front_self");
  EXPECT_EQ(loadWith("").cases[0].metric, "");  // the primary error, front_rms
  for (const char* bad : {R"(, "metric": "pressure_l2")", R"(, "metric": "front_self")"}) {
    try {
      loadWith(bad);
      ADD_FAILURE() << bad << " loaded";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("/cases/0/metric"), std::string::npos) << e.what();
    }
  }
}
