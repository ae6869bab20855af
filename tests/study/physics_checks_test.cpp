// The stability criteria on synthetic frames whose answers are known by construction: a tank at rest on
// its lattice, the same tank with one particle pushed against the floor, thrown too fast, or lifted.
#include "sphfx/study/physics_checks.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "sphfx/core/error.h"

using namespace sphfx;
using namespace sphfx::study;

namespace {

// A 0.2 x 0.1 x 0.1 tank filled to 0.1 m at spacing 0.01 (10 x 10 x 10 particles), g = 9.81.
Scene tankScene() {
  schema::Json raw = schema::Json::parse(R"({
    "domain": { "min": [0, 0, 0], "max": [0.1, 0.2, 0.1] },
    "fluid": { "spacing": 0.01, "blocks": [ { "shape": "box", "min": [0, 0, 0], "max": [0.1, 0.1, 0.1] } ] },
    "time": { "fps": 10, "start_frame": 1, "end_frame": 3 }
  })");
  return parseScene(raw, "tank");
}

ParticleFrame restingFrame(const Scene& scene, int frame) {
  const SeededParticles seeds = seedParticles(scene);
  ParticleFrame f;
  f.frame = frame;
  f.time = scene.frameTime(frame);
  f.particleSpacing = scene.fluid.spacing;
  f.position = seeds.position;
  f.velocity = seeds.velocity;
  f.density.assign(f.size(), float(scene.fluid.restDensity));
  return f;
}

std::vector<FrameState> states(const Scene& scene, const std::vector<ParticleFrame>& frames) {
  std::vector<FrameState> s;
  for (const auto& f : frames) s.push_back(measureFrameState(f, scene, particleBounds(scene)));
  return s;
}

// A miss of the criterion whose worst frame is `frame` and whose measured text contains `text`.
void expectMiss(const CriterionResult& r, int frame, const std::string& text) {
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.worstFrame, frame);
  EXPECT_NE(r.measured.find(text), std::string::npos) << r.measured;
}

}  // namespace

TEST(PhysicsChecks, ATankAtRestOnItsLatticeMeetsEveryCriterion) {
  const Scene scene = tankScene();
  const auto st = states(scene, {restingFrame(scene, 1), restingFrame(scene, 2), restingFrame(scene, 3)});
  EXPECT_NEAR(st[0].surfaceHeight, 0.1, 1e-6);
  EXPECT_NEAR(st[0].closest.wallGap, 0.005, 1e-6);
  EXPECT_NEAR(st[0].bulkDensityRatio, 1.0, 1e-9);
  // Mean height 0.05 m: E/m = g * 0.05.
  EXPECT_NEAR(st[0].energyPerMass, 9.81 * 0.05, 1e-5);
  for (Criterion c : {Criterion::Rest, Criterion::Energy, Criterion::Walls, Criterion::Speed})
    EXPECT_TRUE(judge(c, st, scene).passed) << toString(c) << ": " << judge(c, st, scene).measured;
  // The figures alone, as the stability report's table of runs prints them.
  // KE/m bound 0.5e-4 g H and speed bound 2 sqrt(g H), H = 0.1 m.
  EXPECT_EQ(judge(Criterion::Rest, st, scene).figure,
            "drift 0.000 spacings, bulk +0.00 %, KE/m 0.00e+00 J/kg (bound 4.90e-05)");
  EXPECT_EQ(judge(Criterion::Energy, st, scene).figure, "+0.000 % of g H");
  EXPECT_EQ(judge(Criterion::Walls, st, scene).figure, "0.500 spacings");
  EXPECT_EQ(judge(Criterion::Speed, st, scene).figure,
            fmt::format("0.000 m/s (bound {:.3f})", 2 * std::sqrt(9.81 * 0.1)));
}

TEST(PhysicsChecks, AMissSaysHowManyParticlesBreakTheBoundAndInHowManyFrames) {
  const Scene scene = tankScene();
  const ParticleFrame rest = restingFrame(scene, 1);
  // Frame 2: one centre 0.04 spacings above the floor (the worst); frame 3: three at 0.06.
  ParticleFrame one = restingFrame(scene, 2), three = restingFrame(scene, 3);
  one.position[0][1] = 0.0004f;
  for (int i : {0, 1, 2}) three.position[i][1] = 0.0006f;
  expectMiss(judge(Criterion::Walls, states(scene, {rest, one, three}), scene), 2,
             "; 1 particle nearer than the bound in that frame (up to 3 in one), 2 frames with any");

  // Frame 2: two particles faster than the bound, the faster of them the worst; no other frame.
  ParticleFrame fast = restingFrame(scene, 2);
  fast.velocity[100] = {float(1.01 * speedBound(scene)), 0, 0};
  fast.velocity[600] = {0, float(-1.02 * speedBound(scene)), 0};
  expectMiss(judge(Criterion::Speed, states(scene, {rest, fast, rest}), scene), 2,
             "; 2 particles faster than the bound in that frame (up to 2 in one), 1 frame with any");

  // A pass says nothing of the kind.
  for (Criterion c : {Criterion::Walls, Criterion::Speed})
    EXPECT_EQ(judge(c, states(scene, {rest, rest}), scene).measured.find("than the bound"),
              std::string::npos);
}

TEST(PhysicsChecks, BoundsFollowFromTheScene) {
  const Scene scene = tankScene();
  EXPECT_NEAR(initialFluidHeight(scene), 0.1, 1e-6);                // float positions
  EXPECT_NEAR(speedBound(scene), 2 * std::sqrt(9.81 * 0.1), 1e-6);  // Ritter's front speed
}

TEST(PhysicsChecks, EachViolationIsCaught) {
  const Scene scene = tankScene();
  const ParticleFrame rest = restingFrame(scene, 1);

  ParticleFrame pressed = restingFrame(scene, 2);
  pressed.position[0][1] = 0.0005f;  // 0.05 s above the floor: only the last-resort clamp holds it
  expectMiss(judge(Criterion::Walls, states(scene, {rest, pressed}), scene), 2,
             "0.050 spacings from the domain's y-min wall");

  ParticleFrame fast = restingFrame(scene, 2);
  fast.velocity[500] = {0, 0, float(1.01 * speedBound(scene))};
  const CriterionResult thrown = judge(Criterion::Speed, states(scene, {rest, fast}), scene);
  EXPECT_FALSE(thrown.passed);
  // The miss names its frame and place: the thrown particle's centre and the nearest wall (the tank's
  // faces, the lid at y = 0.2 among them), its distance in spacings.
  const auto& p = fast.position[500];
  const char* faces[6] = {"x-min", "x-max", "y-min", "y-max", "z-min", "z-max"};
  double gap = 1e30;
  int nearest = 0;
  for (int k = 0; k < 6; ++k) {
    const double d = k % 2 ? (k == 3 ? 0.2 : 0.1) - p[k / 2] : p[k / 2];
    if (d < gap) gap = d, nearest = k;
  }
  EXPECT_EQ(thrown.worstFrame, 2);
  EXPECT_NE(thrown.measured.find(
                fmt::format("at ({:.4f}, {:.4f}, {:.4f}) m, {:.3f} spacings from the domain's {} wall", p[0],
                            p[1], p[2], gap / 0.01, faces[nearest])),
            std::string::npos)
      << thrown.measured;
  ParticleFrame lifted = restingFrame(scene, 2);
  for (auto& p : lifted.position) p[1] += 0.002f;  // E/m grows by g * 0.002 = 2 % of g H
  EXPECT_FALSE(judge(Criterion::Energy, states(scene, {rest, lifted}), scene).passed);
  ParticleFrame risen = restingFrame(scene, 2);
  for (auto& p : risen.position) p[1] += 0.006f;  // surface 0.6 s higher
  EXPECT_FALSE(judge(Criterion::Rest, states(scene, {rest, risen}), scene).passed);

  ParticleFrame expanded = restingFrame(scene, 2);
  expanded.density.assign(expanded.size(), float(0.99 * scene.fluid.restDensity));
  EXPECT_FALSE(judge(Criterion::Rest, states(scene, {rest, expanded}), scene).passed);

  ParticleFrame stirred = restingFrame(scene, 2);
  for (auto& v : stirred.velocity) v = {0.02f, 0, 0};  // rms 2 % of sqrt(g H): KE/m = 2e-4 > 0.5e-4 g H
  EXPECT_FALSE(judge(Criterion::Rest, states(scene, {rest, stirred}), scene).passed);
}

// Without vertical gravity (a periodic vortex) g H is 0: the energy bound is 1 % of the starting E/m.
TEST(PhysicsChecks, WithoutGravityEnergyGainIsMeasuredAgainstTheStartingEnergy) {
  Scene scene = tankScene();
  scene.gravity = {0, 0, 0};
  ParticleFrame moving = restingFrame(scene, 1);
  for (auto& v : moving.velocity) v = {0.1f, 0, 0};  // E/m = 0.005 J/kg
  ParticleFrame slower = restingFrame(scene, 2), faster = restingFrame(scene, 2);
  for (auto& v : slower.velocity) v = {0.09f, 0, 0};
  for (auto& v : faster.velocity) v = {0.1015f, 0, 0};  // E/m 3 % above the start
  const CriterionResult kept = judge(Criterion::Energy, states(scene, {moving, slower}), scene);
  EXPECT_TRUE(kept.passed) << kept.measured;
  EXPECT_NE(kept.measured.find("+0.000 % of the starting E/m"), std::string::npos) << kept.measured;
  const CriterionResult gained = judge(Criterion::Energy, states(scene, {moving, faster}), scene);
  EXPECT_FALSE(gained.passed) << gained.measured;
  EXPECT_NE(gained.measured.find("+3.0"), std::string::npos) << gained.measured;
}

// Fluid that enters or leaves (an emitter, a kill box, an open face) is no closed system: rest and energy
// are not judged there, walls and speed are.
TEST(PhysicsChecks, RestAndEnergyAreNotJudgedWhereFluidEntersOrLeaves) {
  Scene scene = tankScene();
  scene.kill = {KillBox{{0.3, 0.3, 0.3}, {0.4, 0.4, 0.4}}};
  ParticleFrame lifted = restingFrame(scene, 2);
  for (auto& p : lifted.position) p[1] += 0.02f;  // a gain that fails the closed tank's energy bound
  const auto st = states(scene, {restingFrame(scene, 1), lifted});
  for (Criterion c : {Criterion::Rest, Criterion::Energy}) {
    const CriterionResult r = judge(c, st, scene);
    EXPECT_FALSE(r.judged) << toString(c);
    EXPECT_TRUE(r.passed) << toString(c);
  }
  EXPECT_TRUE(judge(Criterion::Walls, st, scene).judged);
  EXPECT_TRUE(judge(Criterion::Speed, st, scene).judged);
  scene.kill.clear();
  EXPECT_FALSE(judge(Criterion::Energy, st, scene).passed) << "the closed tank's gain";
}

TEST(PhysicsChecks, RestAndEnergyAreNotJudgedWhereACollidersWorkEntersTheFluid) {
  Scene scene = tankScene();
  ParticleFrame lifted = restingFrame(scene, 2);
  for (auto& p : lifted.position) p[1] += 0.02f;  // a gain that fails the closed tank's energy bound
  const auto st = states(scene, {restingFrame(scene, 1), lifted});
  // A collider at rest takes no part in the energy balance; a keyframed one does work on the fluid.
  Collider post;
  post.shape = Shape::Box;
  post.min = {0.04, 0.0, 0.04};
  post.max = {0.06, 0.05, 0.06};
  scene.colliders = {post};
  EXPECT_TRUE(judge(Criterion::Energy, st, scene).judged) << "a collider at rest";
  EXPECT_FALSE(judge(Criterion::Energy, st, scene).passed);
  Keyframe start, end;
  end.time = 1.0;
  end.offset = {0.0, 0.1, 0.0};
  scene.colliders[0].keyframes = {start, end};
  for (Criterion c : {Criterion::Rest, Criterion::Energy}) {
    const CriterionResult r = judge(c, st, scene);
    EXPECT_FALSE(r.judged) << toString(c) << " with a moving collider";
    EXPECT_TRUE(r.passed) << toString(c);
  }
}

TEST(PhysicsChecks, CriterionNames) {
  EXPECT_EQ(parseCriterion("rest"), Criterion::Rest);
  EXPECT_EQ(parseCriterion("walls"), Criterion::Walls);
  EXPECT_THROW(parseCriterion("completed"), InputError);
}
