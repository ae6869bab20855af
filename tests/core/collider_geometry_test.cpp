// Collider geometry: the mesh readers against files written independently (tests/common/test_meshes.h),
// closedness, rigid motion against hand-computed rotations, distance fields against the analytic
// distance of a box and a sphere, the field cache, and each bad input's error.
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>

#include "../common/test_meshes.h"
#include "sphfx/core/collider_geometry.h"
#include "sphfx/core/collider_motion.h"
#include "sphfx/core/error.h"
#include "sphfx/core/vdb_io.h"

using namespace sphfx;
namespace fs = std::filesystem;

namespace {

fs::path testDir(const std::string& name) {
  return test::freshTestDir("collider_geometry_" + name);
}

void writeText(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

Collider meshCollider(const fs::path& file) {
  Collider c;
  c.shape = Shape::Mesh;
  c.file = file.string();
  return c;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

double boxDistance(const Vec3d& p, const Vec3d& lo, const Vec3d& hi) {
  double outside2 = 0, inside = -1e300;
  for (int a = 0; a < 3; ++a) {
    const double d = std::max(lo[a] - p[a], p[a] - hi[a]);
    if (d > 0) outside2 += d * d;
    inside = std::max(inside, d);
  }
  return outside2 > 0 ? std::sqrt(outside2) : inside;
}

}  // namespace

TEST(ColliderGeometry, ObjQuadsAndStlFormatsReadTheSameSurface) {
  const fs::path d = testDir("formats");
  test::writeBoxObj((d / "box.obj").string(), {0, 0, 0}, {1, 2, 3});
  const TriangleMesh box = readColliderMesh((d / "box.obj").string());
  EXPECT_EQ(box.positions.size(), 8u);
  EXPECT_EQ(box.triangles.size(), 12u);  // 6 quads fanned
  EXPECT_EQ(countOpenEdges(box), 0u);
  // Negative (relative) indices and v/t/n tokens name the same vertices.
  writeText(d / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf -3/1/1 -2/1/1 -1//1\n");
  const TriangleMesh tri = readColliderMesh((d / "tri.obj").string());
  ASSERT_EQ(tri.triangles.size(), 1u);
  EXPECT_EQ(tri.triangles[0], (std::array<uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(countOpenEdges(tri), 3u);

  test::writeSphereStl((d / "sphere.stl").string(), {0, 0, 0}, 1.0, 8, 16);
  const TriangleMesh sphere = readColliderMesh((d / "sphere.stl").string());
  EXPECT_EQ(sphere.triangles.size(), size_t(2 * 16 * 7));
  EXPECT_EQ(countOpenEdges(sphere), 0u);  // welded by position: closed
  for (const auto& p : sphere.positions)
    EXPECT_NEAR(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), 1.0, 1e-6);

  test::writeQuadStl((d / "quad.stl").string(), 0, 1, 0.5, 0, 1);
  const TriangleMesh quad = readColliderMesh((d / "quad.stl").string());
  EXPECT_EQ(quad.triangles.size(), 2u);
  EXPECT_EQ(countOpenEdges(quad), 4u);
}

TEST(ColliderGeometry, MalformedFilesNameFileAndLine) {
  const fs::path d = testDir("bad");
  writeText(d / "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  EXPECT_NE(errorOf([&] { readColliderMesh((d / "nan.obj").string()); }).find("nan.obj:3: vertex coordinate"),
            std::string::npos);
  writeText(d / "index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  EXPECT_NE(errorOf([&] {
              readColliderMesh((d / "index.obj").string());
            }).find("index.obj:4: vertex index 4 out of range"),
            std::string::npos);
  writeText(d / "empty.obj", "# nothing\nv 0 0 0\n");
  EXPECT_NE(errorOf([&] { readColliderMesh((d / "empty.obj").string()); }).find("empty.obj: no triangles"),
            std::string::npos);
  writeText(d / "short.stl", "solid x\nfacet normal 0 0 1\n outer loop\n  vertex 0 0\n");
  EXPECT_NE(errorOf([&] { readColliderMesh((d / "short.stl").string()); }).find("short.stl:4: expected"),
            std::string::npos);
  writeText(d / "mesh.dae", "<collada/>");
  EXPECT_NE(errorOf([&] { readColliderMesh((d / "mesh.dae").string()); }).find("unknown mesh format"),
            std::string::npos);
  EXPECT_THROW(readColliderMesh((d / "missing.obj").string()), IoError);
  // A mesh that is not closed, without a thickness, is refused naming its open edges.
  test::writeQuadStl((d / "quad.stl").string(), 0, 1, 0.5, 0, 1);
  Scene scene;
  scene.colliders = {meshCollider(d / "quad.stl")};
  EXPECT_NE(errorOf([&] {
              checkColliderGeometry(scene);
            }).find("/colliders/0: " + (d / "quad.stl").string() + ": the mesh is not closed (4 open edges)"),
            std::string::npos);
  scene.colliders[0].thickness = 0.02;
  EXPECT_EQ(checkColliderGeometry(scene), std::vector<size_t>{2});
}

TEST(ColliderGeometry, PoseRotatesAboutThePivotAtTheSlerpRate) {
  Collider c;
  c.shape = Shape::Box;
  c.min = {0, 0, 0};
  c.max = {2, 2, 2};  // pivot (1, 1, 1)
  Keyframe k0, k1;
  k1.time = 2;
  k1.offset = {2, 0, 0};
  k1.rotation = {0, 90, 0};
  c.keyframes = {k0, k1};
  const ColliderPose mid = colliderPose(c, 1.0);
  // Halfway: 45 degrees about +y, the pivot moved by (1, 0, 0); omega = (pi/2) / 2 s about y.
  EXPECT_NEAR(mid.angularVelocity[1], std::numbers::pi / 4, 1e-12);
  EXPECT_NEAR(mid.velocity[0], 1.0, 1e-12);
  const Vec3d x = mid.toWorld({2, 1, 1});  // one unit +x of the pivot, rotated 45 degrees about +y
  EXPECT_NEAR(x[0], 2 + std::cos(std::numbers::pi / 4), 1e-12);
  EXPECT_NEAR(x[2], 1 - std::sin(std::numbers::pi / 4), 1e-12);
  const Vec3d back = mid.toRest(x);
  EXPECT_NEAR(back[0], 2, 1e-12);
  EXPECT_NEAR(back[2], 1, 1e-12);
  // Material velocity = v + omega x r, r = x - pivot - offset.
  const Vec3d v = mid.velocityAt(x);
  const double r = 1, w = std::numbers::pi / 4;
  EXPECT_NEAR(std::hypot(v[0] - 1, v[2]), w * r, 1e-12);
  // Held before the first key and after the last.
  EXPECT_NEAR(colliderPose(c, 5).toWorld({2, 1, 1})[2], 0.0, 1e-12);
  EXPECT_EQ(colliderPose(c, 5).angularVelocity[1], 0.0);
  // Euler degrees: x first, then y, then z about fixed axes.
  const Vec3d e = rotate(quatFromEulerDegrees({90, 90, 0}), {0, 1, 0});  // y -> z (about x) -> x (about y)
  EXPECT_NEAR(e[0], 1, 1e-12);
}

TEST(ColliderGeometry, MeshFieldMatchesTheAnalyticBoxDistance) {
  const fs::path d = testDir("field");
  test::writeBoxObj((d / "box.obj").string(), {-0.1, -0.05, -0.1}, {0.1, 0.05, 0.1});
  Collider c = meshCollider(d / "box.obj");
  c.scale = 2;
  c.rotation = {0, 90, 0};
  c.translation = {1, 0.5, 0};
  // Placed: scale 2 -> [-0.2,0.2]x[-0.1,0.1]x[-0.2,0.2], 90 degrees about y keeps it, then +(1, 0.5, 0).
  const Vec3d lo{0.8, 0.4, -0.2}, hi{1.2, 0.6, 0.2};
  const FieldSpec spec{0.01, 0.06, 0.02};
  const ColliderField f = buildColliderField(c, 0, spec);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(f.solidMin[a], lo[a], 1e-6);
    EXPECT_NEAR(f.solidMax[a], hi[a], 1e-6);
  }
  // Inside the narrow bands the field is the exact distance (OpenVDB's is exact up to float rounding
  // at voxel centres; trilinear interpolation of a distance that is linear per face adds error only
  // near edges, bounded by the voxel size).
  double worst = 0;
  for (double x = 0.75; x <= 1.25; x += 0.0037)
    for (double y = 0.35; y <= 0.65; y += 0.0041) {
      const Vec3d p{x, y, 0.013};
      const double exact = boxDistance(p, lo, hi);
      if (exact > spec.exteriorBand || exact < -spec.interiorDepth) continue;
      worst = std::max(worst, std::fabs(f.sample(p) - exact));
    }
  std::printf("box field: worst |error| %.2e m (voxel %.2e m)\n", worst, spec.voxel);
  EXPECT_LT(worst, 0.5 * spec.voxel);
}

TEST(ColliderGeometry, VdbLevelSetFieldMatchesTheSphereAndIsCached) {
  openvdb::initialize();
  const fs::path d = testDir("vdb");
  // A level set written as Houdini writes one: a float grid of class level set, with a fog grid beside.
  auto sphere =
      openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(0.5f, openvdb::Vec3f(0, 0, 0), 0.02f);
  sphere->setName("rock");
  auto fog = openvdb::FloatGrid::create();
  fog->setName("density");
  fog->setGridClass(openvdb::GRID_FOG_VOLUME);
  fog->tree().setValue({0, 0, 0}, 1.0f);
  writeVdbFile((d / "rock.vdb").string(), {fog, sphere});
  Collider c;
  c.shape = Shape::Vdb;
  c.file = (d / "rock.vdb").string();
  c.scale = 0.5;  // radius 0.25
  c.translation = {0.3, 0.2, 0.1};
  // The first float grid is the fog volume: refused by name, as is a grid that is not there.
  EXPECT_NE(errorOf([&] { colliderRestMesh(c); }).find("grid \"density\" is a fog volume"),
            std::string::npos);
  c.grid = "nope";
  EXPECT_NE(errorOf([&] { colliderRestMesh(c); }).find("no grid \"nope\" (grids: density, rock)"),
            std::string::npos);
  c.grid = "rock";
  const FieldSpec spec{0.01, 0.05, 0.02};
  const std::string cache = (d / "shot/colliders/collider.0.vdb").string();
  bool rebuilt = false;
  const ColliderField f = buildColliderField(c, 0, spec, cache, &rebuilt);
  EXPECT_TRUE(rebuilt);
  double worst = 0;
  for (double r = 0.2; r <= 0.27; r += 0.003)
    for (double th = 0.1; th < 3.1; th += 0.37) {
      const Vec3d p{0.3 + r * std::sin(th), 0.2 + r * std::cos(th), 0.1 + 0.3 * r * std::sin(th)};
      const double exact =
          std::sqrt(std::pow(p[0] - 0.3, 2) + std::pow(p[1] - 0.2, 2) + std::pow(p[2] - 0.1, 2)) - 0.25;
      worst = std::max(worst, std::fabs(f.sample(p) - exact));
    }
  // The sphere passes through a mesh of the source's zero level set (voxel 0.01 at this scale): its
  // facets sit within a small fraction of a voxel of the sphere.
  std::printf("vdb sphere field: worst |error| %.2e m (voxel %.2e m)\n", worst, spec.voxel);
  EXPECT_LT(worst, 0.5 * spec.voxel);
  // A second build reads the cache: same values, no rebuild; a changed placement rebuilds.
  const ColliderField again = buildColliderField(c, 0, spec, cache, &rebuilt);
  EXPECT_FALSE(rebuilt);
  EXPECT_EQ(again.distance, f.distance);
  EXPECT_EQ(again.solidMin, f.solidMin);
  c.translation[0] = 0.31;
  buildColliderField(c, 0, spec, cache, &rebuilt);
  EXPECT_TRUE(rebuilt);
}

TEST(ColliderGeometry, OpenMeshWithThicknessIsAShell) {
  const fs::path d = testDir("shell");
  test::writeQuadStl((d / "plate.stl").string(), 0, 1, 0.5, 0, 1);
  Collider c = meshCollider(d / "plate.stl");
  c.thickness = 0.02;
  const FieldSpec spec{0.01, 0.05, 0.02};
  const ColliderField f = buildColliderField(c, 0, spec);
  EXPECT_NEAR(f.sample({0.5, 0.5, 0.5}), -0.01, 1e-3);    // mid-plane: half the thickness deep
  EXPECT_NEAR(f.sample({0.5, 0.52, 0.5}), 0.01, 1e-3);    // above
  EXPECT_NEAR(f.sample({0.5, 0.485, 0.5}), 0.005, 1e-3);  // below
  EXPECT_NEAR(f.solidMin[1], 0.49, 1e-6);
  EXPECT_NEAR(f.solidMax[1], 0.51, 1e-6);
}
