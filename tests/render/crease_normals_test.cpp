// Collider meshes keep hard edges and smooth curves: a cube's corners get their own face's normal, a
// fine UV sphere's corners the radial direction.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer.h"

using namespace sphfx;

TEST(CreaseNormals, CubeCornersTakeTheirFaceNormalAndSpheresStaySmooth) {
  // The cube as a welded mesh (8 vertices), the way mesh files come: smooth vertex normals would be
  // diagonal.
  TriangleMesh cube;
  for (int k = 0; k < 8; ++k)
    cube.positions.push_back({float(k & 1), float((k >> 1) & 1), float((k >> 2) & 1)});
  cube.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                    {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  const TriangleMesh hard = render::withCreaseNormals(cube, 40);
  ASSERT_EQ(hard.positions.size(), 36u);
  for (size_t t = 0; t < hard.triangles.size(); ++t) {
    const auto& a = hard.positions[hard.triangles[t][0]];
    const auto& b = hard.positions[hard.triangles[t][1]];
    const auto& c = hard.positions[hard.triangles[t][2]];
    const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
    for (uint32_t v : hard.triangles[t])
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(hard.normals[v][k], n[k], 1e-6) << "triangle " << t;  // unit area 1/2 * 2
  }
  const TriangleMesh sphere = render::withCreaseNormals(render::makeUvSphere({0, 0, 0}, 1, 32, 64), 40);
  double worst = 1;
  for (size_t i = 0; i < sphere.positions.size(); ++i) {
    const auto& p = sphere.positions[i];
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    worst = std::min(
        worst, (p[0] * sphere.normals[i][0] + p[1] * sphere.normals[i][1] + p[2] * sphere.normals[i][2]) / r);
  }
  EXPECT_GT(worst, 0.99);  // within 8 degrees of radial everywhere (the poles' fans included)
}
