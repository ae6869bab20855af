// Colliders: a moving box pushes fluid; no particle is ever inside a collider or outside the domain
// (every frame); the shipped box_emerge scene runs without health stops; scenes without colliders
// compile no collider code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "gpu_types.h"
#include "sim_shaders.h"
#include "sim_test_util.h"
#include "simulator.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/shader_program.h"

using namespace sphfx;

namespace {

// Collider offset at time t: linear between keys, held outside them (independent of the GLSL).
Vec3d colliderOffset(const Collider& c, double t) {
  if (c.keyframes.empty()) return {0, 0, 0};
  if (t <= c.keyframes.front().time) return c.keyframes.front().offset;
  for (size_t k = 1; k < c.keyframes.size(); ++k) {
    const Keyframe &a = c.keyframes[k - 1], &b = c.keyframes[k];
    if (t < b.time) {
      const double s = (t - a.time) / (b.time - a.time);
      Vec3d o{};
      for (int i = 0; i < 3; ++i) o[i] = a.offset[i] + s * (b.offset[i] - a.offset[i]);
      return o;
    }
  }
  return c.keyframes.back().offset;
}

struct Violations {
  size_t insideCollider = 0, outsideDomain = 0;
};

// Particles strictly inside a (box) collider placed for the frame's time, or outside the domain.
Violations check(const Scene& s, const ParticleFrame& f) {
  Violations v;
  for (const auto& p : f.position) {
    for (int a = 0; a < 3; ++a)
      if (!(p[a] >= s.domain.min[a] && p[a] <= s.domain.max[a])) {
        ++v.outsideDomain;
        break;
      }
    for (const Collider& c : s.colliders) {
      const Vec3d o = colliderOffset(c, f.time);
      bool inside = true;
      for (int a = 0; a < 3; ++a) {
        if (c.shape == Shape::Box) inside = inside && p[a] > c.min[a] + o[a] && p[a] < c.max[a] + o[a];
      }
      if (c.shape == Shape::Sphere) {
        double d2 = 0;
        for (int a = 0; a < 3; ++a) d2 += std::pow(p[a] - (c.center[a] + o[a]), 2);
        inside = d2 < c.radius * c.radius;
      }
      v.insideCollider += inside;
    }
  }
  return v;
}

TEST(Colliders, MovingBoxPushesFluidAndNothingEntersIt) {
  auto ctx = test::makeContext();
  // A wall-to-wall paddle (a box filling the tank's depth) moves +x at 0.5 m/s through a resting layer.
  const Scene scene = test::sceneFromJson(
      R"({"domain": {"min": [0,0,0], "max": [0.6,0.3,0.08]},
      "fluid": {"spacing": 0.02, "blocks": [{"min": [0.1,0,0], "max": [0.6,0.12,0.08]}]},
      "colliders": [{"name": "paddle", "shape": "box", "min": [0.04,0.0,0.0], "max": [0.1,0.3,0.08],
                     "keyframes": [{"time": 0.0, "offset": [0,0,0]}, {"time": 0.4, "offset": [0.2,0,0]}]}],
      "time": {"fps": 30, "start_frame": 0, "end_frame": 9}})");
  ASSERT_TRUE(sim::simShaderDefines(scene).has("HAS_COLLIDERS"));
  sim::Simulator sim(scene);
  ParticleFrame f;
  double pushed = 0;
  while (sim.frame() < scene.time.endFrame) {
    sim.advance();
    f = sim.cacheFrame();
    const Violations v = check(scene, f);
    EXPECT_EQ(v.insideCollider, 0u) << "frame " << sim.frame();
    EXPECT_EQ(v.outsideDomain, 0u) << "frame " << sim.frame();
    // Mean x velocity of the fluid within two spacings ahead of the paddle's front face.
    const double front = scene.colliders[0].max[0] + colliderOffset(scene.colliders[0], f.time)[0];
    double sum = 0;
    int n = 0;
    for (size_t i = 0; i < f.size(); ++i)
      if (f.position[i][0] > front && f.position[i][0] < front + 2 * scene.fluid.spacing) {
        sum += f.velocity[i][0];
        ++n;
      }
    if (n > 0 && f.time < 0.4) pushed = sum / n;
    std::printf("frame %d: paddle front %.3f, %d particles ahead, mean vx %.3f m/s\n", sim.frame(), front, n,
                n ? sum / n : 0.0);
  }
  // The fluid right ahead of the paddle moves with it (0.5 m/s) rather than resting: at least half the
  // paddle's speed while the paddle still moves.
  EXPECT_GT(pushed, 0.25);
}

TEST(Colliders, BoxEmergeRunsWithoutHealthStops) {
  auto ctx = test::makeContext();
  // The shipped scene at CI resolution, over the box's whole rise (1 s to 4 s) at 12 fps.
  const Scene scene =
      loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/box_emerge.json",
                {"fluid.spacing=0.04", "time.fps=12", "time.start_frame=0", "time.end_frame=54"});
  sim::Simulator sim(scene);
  size_t worstInside = 0, worstOutside = 0;
  double maxTop = 0;
  while (sim.frame() < scene.time.endFrame) {
    ASSERT_NO_THROW(sim.advance()) << "frame " << sim.frame() + 1;
    const ParticleFrame f = sim.cacheFrame();
    const Violations v = check(scene, f);
    worstInside = std::max(worstInside, v.insideCollider);
    worstOutside = std::max(worstOutside, v.outsideDomain);
    for (const auto& p : f.position) maxTop = std::max(maxTop, double(p[1]));
  }
  std::printf("box_emerge: %u particles, highest particle %.3f m\n", sim.particleCount(), maxTop);
  EXPECT_EQ(worstInside, 0u);
  EXPECT_EQ(worstOutside, 0u);
  // The box's top ends at 0.48 m, above the 0.25 m fill: it lifts fluid above the initial surface.
  EXPECT_GT(maxTop, 0.3);
}

// A collider sample beyond a wall weighs nothing, since the wall's own samples stand for the solid there,
// and one crossing the wall's plane weighs psi (d / s + 1/2) between half a spacing beyond and half a
// spacing inside, d its distance inside (sim_boundary_update.comp). A box through the floor whose lattice
// is half a cell off the floor's puts one layer on the plane: half its psi. Wall samples keep theirs.
TEST(Colliders, SamplesBeyondAWallWeighNothing) {
  auto ctx = test::makeContext();
  const Scene scene = test::pillarTank({"fluid.spacing=0.02", "time.end_frame=2"});
  const double s = scene.fluid.spacing;
  const sim::BoundarySamples rest = sim::sampleBoundaries(scene);
  std::map<std::array<long, 3>, size_t> byPlace;  // the scene is static: samples stay at their rest place
  const auto key = [](const auto& x) {
    return std::array<long, 3>{std::lround(x[0] * 1e5), std::lround(x[1] * 1e5), std::lround(x[2] * 1e5)};
  };
  for (size_t i = 0; i < rest.size(); ++i) ASSERT_TRUE(byPlace.emplace(key(rest.rest[i]), i).second);
  sim::Simulator sim(scene);
  const auto placed = sim.boundary().positions().downloadVector<std::array<float, 4>>(sim.boundaryCount());
  ASSERT_EQ(placed.size(), rest.size());
  size_t beyond = 0, onPlane = 0, inside = 0;
  for (const auto& p : placed) {
    const auto it = byPlace.find(key(p));
    ASSERT_NE(it, byPlace.end());
    const double psi = rest.rest[it->second][3];
    if (rest.body[it->second] == sim::BoundarySamples::kWallBody) {
      EXPECT_FLOAT_EQ(p[3], float(psi));
      continue;
    }
    const double weight = std::clamp(double(p[1]) / s + 0.5, 0.0, 1.0);  // the floor is the nearest wall
    EXPECT_NEAR(p[3], psi * weight, 1e-6 * psi) << "collider sample at y = " << p[1];
    beyond += p[1] < -1e-6;
    onPlane += std::fabs(p[1]) <= 1e-6;
    inside += p[1] > 1e-6;
  }
  std::printf("collider samples: %zu beyond the floor, %zu on its plane, %zu inside the domain\n", beyond,
              onPlane, inside);
  EXPECT_GT(beyond, 0u);
  EXPECT_GT(onPlane, 0u);
  EXPECT_GT(inside, 0u);
}

TEST(Colliders, SceneWithoutCollidersCompilesNoColliderCode) {
  auto ctx = test::makeContext();
  const Scene plain = test::sceneFromJson(
      R"({"fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0], "max": [0.2,0.2,0.2]}]}})");
  const ShaderDefines d = sim::simShaderDefines(plain);
  EXPECT_FALSE(d.has("HAS_COLLIDERS"));
  // Nor the colliders' contact (the DFSPH factor pass's and WCSPH's integration's collider code), which
  // a collider brings with fluid.wall_contact on and only then.
  ASSERT_GT(plain.fluid.wallContact, 0);
  EXPECT_FALSE(d.has("SIM_COLLIDER_CONTACT"));
  Scene withCollider = plain;
  withCollider.colliders = test::sceneFromJson(R"({"fluid": {"spacing": 0.02, "blocks": [{"min": [0,0,0],
      "max": [0.2,0.2,0.2]}]}, "colliders": [{"shape": "sphere", "center": [0.5,0.5,0.5], "radius": 0.1}]})")
                               .colliders;
  EXPECT_TRUE(sim::simShaderDefines(withCollider).has("SIM_COLLIDER_CONTACT"));
  withCollider.fluid.wallContact = 0;
  EXPECT_FALSE(sim::simShaderDefines(withCollider).has("SIM_COLLIDER_CONTACT"));
  // The collider code is #if'd out of the source, so the compiled integration pass has no collider
  // buffers at all; with HAS_COLLIDERS it has both.
  auto blocks = [](const ShaderDefines& defines) {
    const ShaderProgram p = ShaderProgram::compute(simShaderTable(), "sim_integrate.comp", defines);
    int n = 0;
    for (const char* name : {"SimColliders", "SimColliderKeys"})
      n += glGetProgramResourceIndex(p.id(), GL_SHADER_STORAGE_BLOCK, name) != GL_INVALID_INDEX;
    return n;
  };
  EXPECT_EQ(blocks(d), 0);
  ShaderDefines with = d;
  with.set("HAS_COLLIDERS");
  EXPECT_EQ(blocks(with), 2) << "the check above would not notice collider code";
}

}  // namespace
