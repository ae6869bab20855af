// Scene parsing: valid scenes resolve and round-trip; errors name file, JSON path and expectation;
// overrides go through the same validation; seeding matches the lattice count.
#include <gtest/gtest.h>

#include <cmath>

#include "sphfx/core/error.h"
#include "sphfx/core/scene.h"

using namespace sphfx;
using Json = schema::Json;

namespace {
const std::string kDir = SPHFX_SOURCE_DIR;

Json minimal() {
  return Json::parse(R"({"fluid": {"blocks": [{"min": [0,0,0], "max": [0.5,0.5,0.5]}]}})");
}

std::string errorOf(const Json& raw) {
  try {
    parseScene(raw, "x.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Scene, DefaultsFillEverything) {
  const Scene s = parseScene(minimal(), "x.json");
  EXPECT_EQ(s.solver.method, Solver::DFSPH);
  EXPECT_EQ(s.solver.dfsph.minDivergenceIterations, 1);  // SPlisHSPlasH's divergence solve
  EXPECT_EQ(s.time.mode, TimeStepMode::Cfl);
  EXPECT_DOUBLE_EQ(s.fluid.restDensity, 1000);
  EXPECT_DOUBLE_EQ(s.gravity[1], -9.81);
  EXPECT_FALSE(s.render.camera.has_value());
  EXPECT_TRUE(s.colliders.empty());
}

// Issue 26: the default shot (README's first command) runs the solver the schema defaults to.
TEST(Scene, TheDefaultShotRunsTheDefaultSolver) {
  EXPECT_EQ(loadScene(kDir + "/scenes/showcase.json").solver.method,
            parseScene(minimal(), "x.json").solver.method);
}

TEST(Scene, ShippedAndTestScenesRoundTrip) {
  for (const std::string file :
       {"/scenes/dam_break.json", "/scenes/hydrostatic.json", "/scenes/box_emerge.json",
        "/scenes/dam_break_splishsplash.json", "/tests/scenes/good/everything.json"}) {
    SCOPED_TRACE(file);
    const Scene a = loadScene(kDir + file);
    const Json resolved = sceneToJson(a);
    const Scene b = parseScene(resolved, "resolved");
    EXPECT_EQ(resolved, sceneToJson(b));  // a fixed point: resolving twice changes nothing
  }
}

TEST(Scene, EverythingSceneValuesArrive) {
  const Scene s = loadScene(kDir + "/tests/scenes/good/everything.json");
  EXPECT_EQ(s.solver.method, Solver::DFSPH);
  EXPECT_EQ(s.solver.dfsph.minIterations, 3);
  EXPECT_EQ(s.solver.dfsph.minDivergenceIterations, 2);
  EXPECT_EQ(s.time.startFrame, 1001);
  ASSERT_EQ(s.colliders.size(), 2u);
  EXPECT_EQ(s.colliders[0].shape, Shape::Sphere);
  EXPECT_DOUBLE_EQ(s.colliders[0].keyframes[1].offset[0], -1);
  EXPECT_TRUE(s.hasCacheAttribute(CacheAttribute::Id));
  EXPECT_FALSE(s.hasCacheAttribute(CacheAttribute::Pressure));
  ASSERT_TRUE(s.render.camera.has_value());
  EXPECT_EQ(s.render.camera->keyframes.size(), 2u);
  EXPECT_EQ(s.render.format, ImageFormat::Exr);
  EXPECT_DOUBLE_EQ(s.frameTime(1001 + 12), 0.5);
}

TEST(Scene, ErrorNamesFilePathAndExpectation) {
  Json raw = minimal();
  raw["fluid"]["blocks"][0]["min"] = "abc";
  EXPECT_EQ(errorOf(raw), "x.json: /fluid/blocks/0/min: expected an array of 3 numbers, got \"abc\"");
}

TEST(Scene, UnknownKeySuggestsNearMiss) {
  Json raw = minimal();
  raw["gravty"] = Json::array({0, -9.81, 0});
  EXPECT_EQ(errorOf(raw), "x.json: /gravty: unknown key \"gravty\" (did you mean \"gravity\"?)");
  raw = minimal();
  raw["zzzzzz"] = 1;
  EXPECT_NE(errorOf(raw).find("valid keys: version, name, domain"), std::string::npos);
}

TEST(Scene, RangesAreEnforced) {
  Json raw = minimal();
  raw["solver"]["wcsph"]["gamma"] = 20;
  EXPECT_EQ(errorOf(raw), "x.json: /solver/wcsph/gamma: expected a number in [1, 10], got 20");
  raw = minimal();
  raw["render"]["samples"] = 0;
  EXPECT_EQ(errorOf(raw), "x.json: /render/samples: expected an integer in [1, 16], got 0");
}

TEST(Scene, OverridesAreValidatedTheSameWay) {
  Json raw = minimal();
  applyOverride(raw, "fluid.viscosity_model=laplacian");
  applyOverride(raw, "fluid.viscosity=0.02");
  applyOverride(raw, "solver.method=dfsph");  // a bare word is a string
  applyOverride(raw, "fluid.blocks.0.max=[0.4,0.4,0.4]");
  const Scene s = parseScene(raw, "x.json");
  EXPECT_DOUBLE_EQ(s.fluid.viscosity, 0.02);
  EXPECT_EQ(s.solver.method, Solver::DFSPH);
  EXPECT_DOUBLE_EQ(s.fluid.blocks[0].max[0], 0.4);

  applyOverride(raw, "fluid.viscosity=\"lots\"");
  EXPECT_EQ(errorOf(raw), "x.json: /fluid/viscosity: expected a number, got \"lots\"");
  EXPECT_THROW(applyOverride(raw, "fluid.blocks.3.min=[0,0,0]"), InputError);
  EXPECT_THROW(applyOverride(raw, "novalue"), InputError);
  EXPECT_THROW(applyOverride(raw, "fluid.viscosity.x=1"), InputError);
}

TEST(Scene, SeedingMatchesLatticeCount) {
  Json raw = minimal();
  raw["fluid"]["spacing"] = 0.1;
  Scene s = parseScene(raw, "x.json");
  auto seeds = seedParticles(s);
  EXPECT_EQ(seeds.position.size(), 125u);  // 5 x 5 x 5
  EXPECT_EQ(countInitialParticles(s), 125u);
  EXPECT_NEAR(seeds.position[0][0], 0.05, 1e-6);  // cell-centred

  // A sphere of radius R at spacing d holds about (4/3 pi R^3) / d^3 particles.
  raw["fluid"]["blocks"][0] = Json::parse(R"({"shape": "sphere", "center": [0.5,0.5,0.5], "radius": 0.4})");
  raw["fluid"]["spacing"] = 0.02;
  s = parseScene(raw, "x.json");
  const double expected = 4.0 / 3.0 * M_PI * std::pow(0.4, 3) / std::pow(0.02, 3);
  EXPECT_NEAR(double(countInitialParticles(s)), expected, 0.02 * expected);
  EXPECT_EQ(seedParticles(s).position.size(), countInitialParticles(s));
  for (const auto& p : seedParticles(s).position) {
    const double r = std::hypot(p[0] - 0.5, p[1] - 0.5, p[2] - 0.5);
    ASSERT_LE(r, 0.4 + 1e-6);
  }
}

TEST(Scene, SyntaxErrorNamesFileAndLine) {
  try {
    loadScene(kDir + "/tests/scenes/bad/syntax_error.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("syntax_error.json: invalid JSON: parse error at line 1"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(loadScene(kDir + "/tests/scenes/does_not_exist.json"), InputError);
}

TEST(Scene, PackingCompressesTheInitialLattice) {
  Json raw = minimal();
  raw["fluid"]["spacing"] = 0.1;
  raw["fluid"]["packing"] = 0.5;
  const Scene s = parseScene(raw, "x.json");
  EXPECT_EQ(countInitialParticles(s), 1000u);                  // 10^3 at half the spacing
  EXPECT_DOUBLE_EQ(s.particleMass(), 1000 * 0.1 * 0.1 * 0.1);  // mass follows the rest spacing
}

TEST(Scene, AParameterNothingReadsIsAnError) {
  Json raw = minimal();  // DFSPH, CFL steps, artificial viscosity
  raw["solver"]["wcsph"]["eos"] = "linear";
  EXPECT_EQ(
      errorOf(raw),
      "x.json: /solver/wcsph: not read with these settings (only when the method is \"wcsph\"); remove it");
  raw = minimal();
  raw["solver"]["method"] = "wcsph";
  raw["solver"]["dfsph"]["max_iterations"] = 300;
  EXPECT_EQ(
      errorOf(raw),
      "x.json: /solver/dfsph: not read with these settings (only when the method is \"dfsph\"); remove it");
  raw = minimal();
  raw["time"]["dt"] = 0.001;
  EXPECT_EQ(errorOf(raw), "x.json: /time/dt: not read with these settings (fixed mode); remove it");
  raw = minimal();
  raw["fluid"]["viscosity"] = 1e-6;
  EXPECT_EQ(errorOf(raw),
            "x.json: /fluid/viscosity: not read with these settings (laplacian model); remove it");
  raw = minimal();
  raw["solver"]["method"] = "wcsph";
  raw["solver"]["wcsph"]["eos"] = "linear";
  raw["solver"]["wcsph"]["gamma"] = 7;
  EXPECT_EQ(errorOf(raw), "x.json: /solver/wcsph/gamma: not read with these settings (tait eos); remove it");
  raw = minimal();
  raw["surface"]["anisotropic"]["lambda"] = 0.95;
  EXPECT_NE(errorOf(raw).find("/surface/anisotropic: not read"), std::string::npos);
  raw["surface"]["method"] = "anisotropic";
  EXPECT_DOUBLE_EQ(parseScene(raw, "x.json").surface.anisotropic.lambda, 0.95);
}

TEST(Scene, MovedKeysStillLoadAtTheirNewPlace) {
  Json raw = minimal();
  raw["solver"]["method"] = "dfsph";
  raw["solver"]["max_iterations"] = 300;
  raw["time"]["fall_factor"] = 0.3;
  Scene s = parseScene(raw, "x.json");
  EXPECT_EQ(s.solver.dfsph.maxIterations, 300);
  EXPECT_DOUBLE_EQ(s.solver.dfsph.fallFactor, 0.3);
  raw["solver"]["dfsph"]["max_iterations"] = 100;  // both places: which one is meant?
  EXPECT_NE(errorOf(raw).find("/solver/max_iterations: given both here and at its new place"),
            std::string::npos);

  raw = minimal();
  raw["solver"]["method"] = "wcsph";
  applyOverride(raw, "solver.eos=linear");  // an old --set path moves too
  applyOverride(raw, "solver.stiffness=5000");
  s = parseScene(raw, "x.json");
  EXPECT_EQ(s.solver.wcsph.eos, EquationOfState::Linear);
  EXPECT_DOUBLE_EQ(s.solver.wcsph.stiffness, 5000);
}

TEST(Scene, SwitchingAChoiceDropsWhatOnlyTheOtherChoicesRead) {
  Json raw = minimal();
  raw["solver"]["wcsph"]["gamma"] = 7;
  raw["time"]["dt_max"] = 0.004;
  raw["fluid"]["artificial_viscosity"] = 0.05;
  applyOverride(raw, "solver.method=dfsph");
  applyOverride(raw, "time.dt_mode=fixed");
  applyOverride(raw, "fluid.viscosity_model=laplacian");
  EXPECT_FALSE(raw["solver"].contains("wcsph"));
  EXPECT_FALSE(raw["time"].contains("dt_max"));
  EXPECT_FALSE(raw["fluid"].contains("artificial_viscosity"));
  const Scene s = parseScene(raw, "x.json");
  EXPECT_EQ(s.solver.method, Solver::DFSPH);
  EXPECT_EQ(s.time.mode, TimeStepMode::Fixed);
  // Setting the choice it already has keeps its own keys.
  raw = minimal();
  raw["solver"]["wcsph"]["gamma"] = 6;
  applyOverride(raw, "solver.method=wcsph");
  EXPECT_DOUBLE_EQ(parseScene(raw, "x.json").solver.wcsph.gamma, 6);
}

TEST(Scene, MethodEnumsAndDocsComeFromTheRegistries) {
  const std::string doc = sceneReferenceMarkdown();
  for (const auto& e : pressureSolverRegistry()) {
    EXPECT_NE(doc.find("\"" + e.name + "\": " + e.description), std::string::npos) << e.name;
    Json raw = minimal();
    raw["solver"]["method"] = e.name;
    EXPECT_EQ(parseScene(raw, "x.json").solver.method, e.id);
    if (!e.parameterGroup.empty()) {
      EXPECT_NE(doc.find("`solver." + e.parameterGroup + "`"), std::string::npos);
    }
  }
  for (const auto& e : surfacingMethodRegistry()) {
    EXPECT_NE(doc.find("\"" + e.name + "\": " + e.description), std::string::npos) << e.name;
    Json raw = minimal();
    raw["surface"]["method"] = e.name;
    EXPECT_EQ(parseScene(raw, "x.json").surface.method, e.id);
    if (!e.parameterGroup.empty()) {
      EXPECT_NE(doc.find("`surface." + e.parameterGroup + "`"), std::string::npos);
    }
  }
}

// Under the artificial model the walls' Monaghan term has the speed F U_w where the fluid's has alpha c
// (the shader scales the fluid's term by wallViscosityMultiple), whatever alpha, c and the EOS are;
// under the laplacian model the walls' term is F times the fluid's.
TEST(Scene, WallViscosityKeepsItsOwnSpeedWhenAlphaAndCChange) {
  for (const char* eos : {"tait", "linear"})
    for (double alpha : {0.01, 0.02, 0.04})
      for (double c : {12.5, 25.0, 50.0}) {
        Json raw = minimal();
        raw["solver"]["method"] = "wcsph";
        raw["fluid"]["artificial_viscosity"] = alpha;
        raw["fluid"]["wall_viscosity_factor"] = 2;
        raw["fluid"]["wall_viscosity_speed"] = 0.5;
        raw["solver"]["wcsph"]["eos"] = eos;
        if (std::string(eos) == "tait")
          raw["solver"]["speed_of_sound"] = c;
        else
          raw["solver"]["wcsph"]["stiffness"] = c * c;
        const Scene s = parseScene(raw, "x.json");
        SCOPED_TRACE(testing::Message() << eos << " alpha " << alpha << " c " << c);
        EXPECT_NEAR(s.soundSpeed(), c, 1e-12 * c);
        EXPECT_NEAR(s.wallViscosityMultiple() * alpha * c, 2 * 0.5, 1e-12);
      }
  Json laplacian = minimal();
  laplacian["fluid"]["viscosity_model"] = "laplacian";
  laplacian["fluid"]["wall_viscosity_factor"] = 0.5;
  EXPECT_DOUBLE_EQ(parseScene(laplacian, "x.json").wallViscosityMultiple(), 0.5);
  Json none = minimal();
  none["fluid"]["viscosity_model"] = "none";
  EXPECT_EQ(parseScene(none, "x.json").wallViscosityMultiple(), 0.0);
  Json freeSlip = minimal();
  freeSlip["fluid"]["wall_viscosity_speed"] = 0;
  EXPECT_EQ(parseScene(freeSlip, "x.json").wallViscosityMultiple(), 0.0);
}

// A scene whose walls' speed is the fluid's alpha c runs as one without the key did: its identity (what
// restart files and the committed reports' digests hold) leaves the key out; another speed is kept.
TEST(Scene, IdentityLeavesOutAWallSpeedEqualToTheFluidsAlphaC) {
  Json raw = minimal();
  raw["solver"]["speed_of_sound"] = 25;
  raw["fluid"]["wall_viscosity_speed"] = 0.5;
  EXPECT_FALSE(sceneIdentityJson(parseScene(raw, "x.json"))["fluid"].contains("wall_viscosity_speed"));
  raw["fluid"]["wall_viscosity_speed"] = 0.6;
  EXPECT_EQ(sceneIdentityJson(parseScene(raw, "x.json"))["fluid"]["wall_viscosity_speed"], 0.6);
  EXPECT_FALSE(sceneIdentityJson(parseScene(minimal(), "x.json"))["fluid"].contains("wall_viscosity_speed"))
      << "the defaults: 0.6 m/s = 0.02 x 30 m/s";
}

// fluid.wall_drag: "viscous" (the walls' term before the choice existed) stays out of a scene's identity;
// wall_friction is read with "friction" alone, and choosing another viscosity model drops both.
TEST(Scene, WallFrictionOnlyWithTheFrictionDrag) {
  Json raw = minimal();
  const Scene viscous = parseScene(raw, "x.json");
  EXPECT_EQ(viscous.fluid.wallDrag, WallDrag::Viscous);
  EXPECT_FALSE(sceneIdentityJson(viscous)["fluid"].contains("wall_drag"));
  raw["fluid"]["wall_friction"] = 0.01;
  EXPECT_EQ(
      errorOf(raw),
      "x.json: /fluid/wall_friction: not read with these settings (artificial model, wall_drag friction); "
      "remove it");
  raw["fluid"]["wall_drag"] = "friction";
  const Scene friction = parseScene(raw, "x.json");
  EXPECT_EQ(friction.fluid.wallDrag, WallDrag::Friction);
  EXPECT_EQ(friction.fluid.wallFriction, 0.01);
  EXPECT_EQ(sceneIdentityJson(friction)["fluid"]["wall_drag"], "friction");
  applyOverride(raw, "fluid.viscosity_model=laplacian");
  EXPECT_FALSE(raw["fluid"].contains("wall_drag"));
  EXPECT_FALSE(raw["fluid"].contains("wall_friction"));
  EXPECT_EQ(parseScene(raw, "x.json").fluid.viscosityModel, ViscosityModel::Laplacian);
}

// solver.dfsph.density_warm_steps qualifies density_warm_share: "flow_limited" by default; with share 0
// nothing reads it (an error to give, left out of the resolved scene), and "all", what a warm start did
// before the key existed, keeps a scene's identity.
TEST(Scene, DfsphWarmStepsOnlyWithAWarmShare) {
  Json raw = minimal();
  raw["solver"]["method"] = "dfsph";
  const Scene defaults = parseScene(raw, "x.json");
  EXPECT_EQ(defaults.solver.dfsph.densityWarmShare, 0.5);
  EXPECT_EQ(defaults.solver.dfsph.densityWarmSteps, DfsphWarmSteps::FlowLimited);
  EXPECT_EQ(sceneIdentityJson(defaults)["solver"]["dfsph"]["density_warm_steps"], "flow_limited");
  EXPECT_EQ(parseScene(sceneToJson(defaults), "x.json").solver.dfsph.densityWarmSteps,
            DfsphWarmSteps::FlowLimited);
  raw["solver"]["dfsph"]["density_warm_share"] = 0;
  EXPECT_FALSE(sceneToJson(parseScene(raw, "x.json"))["solver"]["dfsph"].contains("density_warm_steps"));
  raw["solver"]["dfsph"]["density_warm_steps"] = "flow_limited";
  EXPECT_NE(errorOf(raw).find("/solver/dfsph/density_warm_steps"), std::string::npos) << errorOf(raw);
  raw["solver"]["dfsph"]["density_warm_share"] = 0.8;
  raw["solver"]["dfsph"]["density_warm_steps"] = "all";
  const Scene all = parseScene(raw, "x.json");
  EXPECT_EQ(all.solver.dfsph.densityWarmSteps, DfsphWarmSteps::All);
  EXPECT_FALSE(sceneIdentityJson(all)["solver"]["dfsph"].contains("density_warm_steps"));
  EXPECT_EQ(sceneToJson(all)["solver"]["dfsph"]["density_warm_steps"], "all");
}

// DFSPH's spiky and Wendland C2 densities are solved with the constraint walls only: with push walls the
// scene is refused at density_kernel, naming the kernel; the poly6 density takes push walls.
TEST(Scene, DfsphKernelDensitiesNeedConstraintWalls) {
  Json raw = minimal();
  raw["solver"]["method"] = "dfsph";
  raw["solver"]["dfsph"]["walls"] = "push";
  for (const char* kernel : {"spiky", "wendland_c2"}) {
    raw["solver"]["dfsph"]["density_kernel"] = kernel;
    const std::string error = errorOf(raw);
    EXPECT_NE(error.find("/solver/dfsph/density_kernel"), std::string::npos) << error;
    EXPECT_NE(error.find(std::string("got \"") + kernel + "\""), std::string::npos) << error;
  }
  raw["solver"]["dfsph"]["density_kernel"] = "poly6";
  EXPECT_EQ(parseScene(raw, "x.json").solver.dfsph.densityKernel, DfsphDensityKernel::Poly6);
  raw["solver"]["dfsph"]["walls"] = "constraints";
  raw["solver"]["dfsph"]["density_kernel"] = "wendland_c2";
  EXPECT_EQ(parseScene(raw, "x.json").solver.dfsph.densityKernel, DfsphDensityKernel::WendlandC2);
}

// solver.dfsph.depth_step_factor caps DFSPH's CFL step at factor d / sqrt(|g| H), H the domain's extent
// along gravity (here tilted: 0.6 g along y and 0.8 g along x), and only there: factor 0, WCSPH and fixed
// steps have no cap. A periodic axis holds no column: its share of g H drops out, and gravity along
// periodic axes alone (a channel's driving force) has no cap. A scene without the key keeps its identity
// (the runs before the key existed).
TEST(Scene, DfsphDepthStepIsTheGravityWaveCrossingOfTheDomain) {
  Json raw = minimal();  // domain [0, 1]^3 by default
  raw["domain"] = Json::parse(R"({"min": [0, 0, 0], "max": [0.5, 2.0, 1.0]})");
  raw["gravity"] = Json::array({-8.0, -6.0, 0.0});  // |g| = 10
  raw["fluid"]["spacing"] = 0.02;
  raw["solver"]["method"] = "dfsph";
  const double depth = 0.8 * 0.5 + 0.6 * 2.0;  // the box's extent along g / |g|
  EXPECT_NEAR(parseScene(raw, "x.json").dfsphDepthStep(), 0.4 * 0.02 / std::sqrt(10 * depth), 1e-15)
      << "the default factor 0.4";
  EXPECT_EQ(sceneIdentityJson(parseScene(raw, "x.json"))["solver"]["dfsph"]["depth_step_factor"], 0.4);
  raw["solver"]["dfsph"]["depth_step_factor"] = 0.8;
  EXPECT_NEAR(parseScene(raw, "x.json").dfsphDepthStep(), 0.8 * 0.02 / std::sqrt(10 * depth), 1e-15);
  raw["solver"]["dfsph"]["depth_step_factor"] = 0;
  EXPECT_TRUE(std::isinf(parseScene(raw, "x.json").dfsphDepthStep())) << "factor 0: no cap";
  EXPECT_FALSE(sceneIdentityJson(parseScene(raw, "x.json"))["solver"]["dfsph"].contains("depth_step_factor"));
  raw["solver"]["dfsph"]["depth_step_factor"] = 0.4;
  Json fixed = raw;
  fixed["time"]["dt_mode"] = "fixed";
  EXPECT_NE(errorOf(fixed).find("/solver/dfsph/depth_step_factor: expected 0 with time.dt_mode \"fixed\""),
            std::string::npos)
      << errorOf(fixed);
  fixed["solver"]["dfsph"].erase("depth_step_factor");  // the default: not read with fixed steps
  const Scene fixedScene = parseScene(fixed, "x.json");
  EXPECT_TRUE(std::isinf(fixedScene.dfsphDepthStep()));
  EXPECT_FALSE(sceneToJson(fixedScene)["solver"]["dfsph"].contains("depth_step_factor"))
      << "a resolved scene must parse again";
  Json weightless = raw;
  weightless["gravity"] = Json::array({0, 0, 0});
  EXPECT_TRUE(std::isinf(parseScene(weightless, "x.json").dfsphDepthStep()));
  Json channel = raw;
  channel["domain"]["periodic"] = Json::array({"x"});
  EXPECT_NEAR(parseScene(channel, "x.json").dfsphDepthStep(), 0.4 * 0.02 / std::sqrt(6.0 * 2.0), 1e-15)
      << "only the walled y axis holds a column";
  channel["gravity"] = Json::array({-10.0, 0.0, 0.0});
  EXPECT_TRUE(std::isinf(parseScene(channel, "x.json").dfsphDepthStep())) << "gravity along x only";
  Json wcsph = minimal();
  wcsph["solver"]["method"] = "wcsph";
  EXPECT_TRUE(std::isinf(parseScene(wcsph, "x.json").dfsphDepthStep()));
}
