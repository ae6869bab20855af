// splitImpostors (CPU): which spheres go to point sprites, which to the quad fallback, which are dropped,
// and the occluder ordering, checked against the test's own projection (render_test_util.h).
#include <gtest/gtest.h>

#include <cmath>

#include "render_test_util.h"

using namespace sphfx;
using namespace sphfx::render;

namespace {

constexpr int kW = 320, kH = 240;
constexpr double kFov = 45, kD = 5;
constexpr float kR = 0.05f;

ImpostorSplit split(const std::vector<ParticleInstance>& ps, float radius = kR, double maxPoint = 255) {
  return splitImpostors(ps, radius, test::axisCamera(kD, kFov), kW, kH, maxPoint);
}

/// World x at depth kD - z whose projection is pixel column `px` (the test's own projection inverted).
double worldX(double px, double z) {
  const double f = 1 / std::tan(kFov * M_PI / 360), aspect = double(kW) / kH;
  return (px / kW * 2 - 1) * (kD - z) * aspect / f;
}

bool contains(const std::vector<ParticleInstance>& ps, const ParticleInstance& p) {
  for (const auto& q : ps)
    if (q.position[0] == p.position[0] && q.position[1] == p.position[1] && q.position[2] == p.position[2])
      return true;
  return false;
}

}  // namespace

TEST(ImpostorSplit, PointsQuadsAndDropped) {
  const ParticleInstance centre{{0, 0, 0}, 0};
  // Centre projected 1 px left of the image: the sphere (~4.8 px radius) still shows, GL would clip a
  // point there.
  const ParticleInstance leftEdge{{float(worldX(-1, 0)), 0, 0}, 0};
  // Inside by 2 px: a point.
  const ParticleInstance insideEdge{{float(worldX(2, 0)), 0, 0}, 0};
  // Wholly off screen to the left (centre 10 px out), behind the camera, beyond the far plane (20).
  const ParticleInstance offLeft{{float(worldX(-10, 0)), 0, 0}, 0};
  const ParticleInstance behind{{0, 0, float(kD + 1)}, 0};
  const ParticleInstance beyondFar{{0, 0, float(kD - 21)}, 0};
  // Its front reaches in front of the near plane (0.5): the quad path clips it.
  const ParticleInstance nearCrossing{{0, 0, float(kD - 0.5 - kR / 2)}, 0};
  const ImpostorSplit s = split({centre, leftEdge, insideEdge, offLeft, behind, beyondFar, nearCrossing});
  EXPECT_EQ(s.points.size(), 2u);
  EXPECT_TRUE(contains(s.points, centre));
  EXPECT_TRUE(contains(s.points, insideEdge));
  EXPECT_EQ(s.quads.size(), 2u);
  EXPECT_TRUE(contains(s.quads, leftEdge));
  EXPECT_TRUE(contains(s.quads, nearCrossing));
  EXPECT_EQ(s.culled, 3u);
}

TEST(ImpostorSplit, SpheresBiggerThanTheLargestPointAreQuads) {
  // Radius 0.5 at depth 5: about 0.5 / 5 * 290 = 29 px radius, 58 px across.
  const std::vector<ParticleInstance> ps{{{0, 0, 0}, 0}};
  EXPECT_EQ(split(ps, 0.5f, 255).points.size(), 1u);
  EXPECT_EQ(split(ps, 0.5f, 40).quads.size(), 1u);
}

TEST(ImpostorSplit, OccludersComeFirstNearestFirst) {
  // A column of spheres one behind the other on the axis, far apart (20 radii), shuffled: only the
  // nearest is within 8 radii of its cell's nearest, so it alone is an occluder; the others follow.
  std::vector<ParticleInstance> ps;
  for (int k : {3, 0, 4, 1, 2}) ps.push_back({{0, 0, float(-k * 20 * kR)}, float(k)});
  const ImpostorSplit s = split(ps);
  ASSERT_EQ(s.points.size(), 5u);
  EXPECT_EQ(s.occluders, 1u);
  EXPECT_EQ(s.points[0].speed, 0.f);
  // Touching spheres (2 radii apart): the first five layers (within 8 radii of the nearest) are
  // occluders, nearest first.
  ps.clear();
  for (int k : {6, 2, 0, 5, 3, 1, 4}) ps.push_back({{0, 0, float(-k * 2 * kR)}, float(k)});
  const ImpostorSplit t = split(ps);
  ASSERT_EQ(t.occluders, 5u);
  for (size_t i = 0; i < t.occluders; ++i) EXPECT_EQ(t.points[i].speed, float(i));
}
