// Geometry of the surfacing stage against analytic references (library level).
#include <gtest/gtest.h>

#include <openvdb/tools/FastSweeping.h>
#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

#include "anisotropic.h"
#include "anisotropic_isa.h"
#include "band_distance.h"
#include "sphfx/core/scene.h"
#include "sphfx/surfacing/surfacing.h"
#include "test_util.h"
#include "zhu_bridson.h"

namespace sphfx::surfacing {
namespace {

using test::measure;

SurfaceParams defaultParams(SurfaceMethod method, double spacing) {
  Scene scene;
  sceneSchema().setDefaults(scene);
  SurfaceOverrides o;
  o.method = method;
  SurfaceParams p = resolveParams(spacing, scene.surface, o);
  p.surfaceOffset = calibrateOffset(p);
  return p;
}

struct SphereErrors {
  double volume, area;
  size_t badEdges;
  double meanNormalDot, minNormalDot;  ///< vertex normals against the radial direction
  double meanFaceDot, minFaceDot;      ///< vertex normals against their faces' area-weighted normal
};

/// Mean and minimum of n . m over the vertices, m the unit area-weighted normal of the vertex's
/// triangles: the gradient normals agree with the mesh they are attached to.
std::pair<double, double> faceNormalAgreement(const TriangleMesh& mesh) {
  std::vector<std::array<double, 3>> sum(mesh.positions.size(), {0, 0, 0});
  for (const auto& t : mesh.triangles) {
    const auto &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                 w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    for (uint32_t v : t)
      for (int k = 0; k < 3; ++k) sum[v][k] += n[k];
  }
  double total = 0, least = 1;
  for (size_t i = 0; i < sum.size(); ++i) {
    const auto& m = sum[i];
    const auto& n = mesh.normals[i];
    const double len = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    const double dot = (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]) / len;
    total += dot;
    least = std::min(least, dot);
  }
  return {total / double(sum.size()), least};
}

/// Mean and minimum of n . x / |x| over the vertices: the exact sphere's normals are radial.
std::pair<double, double> radialNormalAgreement(const TriangleMesh& mesh) {
  double sum = 0, least = 1;
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& x = mesh.positions[i];
    const auto& n = mesh.normals[i];
    const double len = std::sqrt(double(x[0]) * x[0] + double(x[1]) * x[1] + double(x[2]) * x[2]);
    const double dot = (n[0] * x[0] + n[1] * x[1] + n[2] * x[2]) / len;
    sum += dot;
    least = std::min(least, dot);
  }
  return {sum / double(mesh.positions.size()), least};
}

SphereErrors sphereErrors(SurfaceMethod method, double radiusInSpacings) {
  const double r = 1.0, s = r / radiusInSpacings;
  const SurfaceParams params = defaultParams(method, s);
  const auto grid = buildLevelSet(test::sphereLattice(r, s), params);
  const TriangleMesh mesh = meshLevelSet(*grid, params.adaptivity);
  const auto m = measure(mesh);
  const auto [meanDot, minDot] = radialNormalAgreement(mesh);
  const auto [meanFace, minFace] = faceNormalAgreement(mesh);
  const double v0 = 4.0 / 3.0 * std::numbers::pi * r * r * r, a0 = 4 * std::numbers::pi * r * r;
  std::printf(
      "%-12s R/s %5.1f: volume %+.2f%%, area %+.2f%% (offset %.3f s); normals . radial: mean %.4f, min %.3f;"
      " . faces: mean %.4f, min %.3f\n",
      methodName(method).c_str(), radiusInSpacings, 100 * (m.volume - v0) / v0, 100 * (m.area - a0) / a0,
      params.surfaceOffset / s, meanDot, minDot, meanFace, minFace);
  return {std::abs(m.volume - v0) / v0,
          std::abs(m.area - a0) / a0,
          m.badEdges,
          meanDot,
          minDot,
          meanFace,
          minFace};
}

// Tolerances at the finest resolution (R = 32 spacings), per method: spheres volume 2 %, area 3 %;
// zhu-bridson 2 % and 2 %; anisotropic 1 % and 1.5 %. R = 32 is in the list because three
// resolutions do not show the trend: zhu-bridson's error at R = 8 is above R = 4's (measured
// 2.2 %, 3.7 %, 2.3 %, 1.1 % volume at R = 4, 8, 16, 32).
struct SphereCase {
  SurfaceMethod method;
  double volumeTol, areaTol;
};

class SphereTest : public ::testing::TestWithParam<SphereCase> {};

TEST_P(SphereTest, ClosedWithVolumeAndAreaConvergingToTheSphere) {
  const SphereCase c = GetParam();
  std::vector<SphereErrors> errors;
  for (double res : {4.0, 8.0, 16.0, 32.0}) errors.push_back(sphereErrors(c.method, res));
  for (const auto& e : errors) {
    EXPECT_EQ(e.badEdges, 0u) << "mesh not closed";
    // Vertex normals from the level set's gradient agree with the mesh's own faces (measured: mean
    // 0.997 or more, min 0.983) and point outward, radial up to the particle-scale bumps of the
    // lattice (mean 0.977 or more, min 0.854, spheres at R/s = 32).
    EXPECT_GT(e.meanFaceDot, 0.995);
    EXPECT_GT(e.minFaceDot, 0.97);
    EXPECT_GT(e.meanNormalDot, 0.97);
    EXPECT_GT(e.minNormalDot, 0.8);
  }
  EXPECT_LT(errors.back().volume, c.volumeTol);
  EXPECT_LT(errors.back().area, c.areaTol);
  // Error falls as the resolution rises.
  EXPECT_LT(errors.back().volume + errors.back().area, errors[0].volume + errors[0].area);
  EXPECT_LT(errors.back().volume, errors[0].volume);
}

INSTANTIATE_TEST_SUITE_P(Methods, SphereTest,
                         ::testing::Values(SphereCase{SurfaceMethod::Spheres, 0.02, 0.03},
                                           SphereCase{SurfaceMethod::ZhuBridson, 0.02, 0.02},
                                           SphereCase{SurfaceMethod::Anisotropic, 0.01, 0.015}),
                         [](const auto& info) {
                           std::string n = methodName(info.param.method);
                           return n == "zhu-bridson" ? std::string("ZhuBridson") : n;
                         });

struct PoolTop {
  double mean, rms;  ///< height of the top surface and its RMS deviation (m)
};

constexpr double kPoolSpacing = 0.1;
constexpr int kPoolWidth = 24, kPoolDepth = 6;

/// The top surface of a jittered resting pool: mesh vertices facing up, away from the walls.
PoolTop poolTop(SurfaceMethod method, int smooth, double jitter) {
  const double s = kPoolSpacing;
  const int n = kPoolWidth;
  SurfaceParams params = defaultParams(method, s);
  params.smoothIterations = smooth;
  params.surfaceOffset = calibrateOffset(params);
  const auto grid = buildLevelSet(test::poolLattice(n, n, kPoolDepth, s, jitter), params);
  const TriangleMesh mesh = meshLevelSet(*grid, 0);
  double sum = 0, sum2 = 0;
  int count = 0;
  for (const auto& p : mesh.positions) {
    const bool inner = p[0] > 4 * s && p[0] < (n - 4) * s && p[1] > 4 * s && p[1] < (n - 4) * s;
    if (!inner || p[2] < (kPoolDepth - 2) * s) continue;
    sum += p[2];
    sum2 += double(p[2]) * p[2];
    ++count;
  }
  EXPECT_GT(count, 100);
  const double mean = sum / count;
  const double rms = std::sqrt(std::max(0.0, sum2 / count - mean * mean));
  std::printf(
      "%-12s smoothing %d, jitter %.2f s: pool top at %.4f m (ideal %.4f), RMS deviation %.5f m = %.4f s\n",
      methodName(method).c_str(), smooth, jitter, mean, kPoolDepth * s, rms, rms / s);
  return {mean, rms};
}

// The kernels themselves, before any smoothing: union-of-spheres bumps against Yu-Turk's flat kernels
// (measured 0.050 s against 0.020 s). Every raw top stays at the fluid's volume: with the raw union of
// spheres the calibrated offset used to open pits (top 0.79 s low, RMS 0.70 s).
TEST(Pool, AnisotropicTopIsFlatterThanSpheres) {
  const PoolTop spheres = poolTop(SurfaceMethod::Spheres, 0, 0.05);
  const PoolTop aniso = poolTop(SurfaceMethod::Anisotropic, 0, 0.05);
  const PoolTop zhuBridson = poolTop(SurfaceMethod::ZhuBridson, 0, 0.05);
  EXPECT_LT(aniso.rms, 0.5 * spheres.rms);
  for (const PoolTop& top : {spheres, aniso, zhuBridson})
    EXPECT_NEAR(top.mean, kPoolDepth * kPoolSpacing, 0.05 * kPoolSpacing);
}

// With the default settings every method puts the top where the particles' volume says (depth * s).
TEST(Pool, DefaultTopSitsAtTheFluidVolume) {
  for (auto m : {SurfaceMethod::Spheres, SurfaceMethod::ZhuBridson, SurfaceMethod::Anisotropic}) {
    const PoolTop top = poolTop(m, 2, 0.05);
    EXPECT_NEAR(top.mean, kPoolDepth * kPoolSpacing, 0.05 * kPoolSpacing) << methodName(m);
    EXPECT_LT(top.rms, 0.05 * kPoolSpacing) << methodName(m);
  }
}

TEST(Anisotropic, KernelShapes) {
  const double s = 0.1;
  AnisotropicSettings settings;
  settings.spacing = s;
  settings.support = 2 * s;
  // An isolated particle: a small sphere (isotropic metric, support k_n * h).
  const auto lone = computeAnisotropicKernels({{0, 0, 0}}, settings);
  ASSERT_EQ(lone.size(), 1u);
  EXPECT_NEAR(lone[0].metric[0], lone[0].metric[3], 1e-3 * lone[0].metric[0]);
  EXPECT_NEAR(lone[0].metric[0], lone[0].metric[5], 1e-3 * lone[0].metric[0]);
  EXPECT_NEAR(lone[0].extent, settings.support * settings.isolatedScale, 1e-6);
  // A flat sheet in z = 0: the kernel of its centre particle is thin along z.
  test::Points sheet;
  for (int i = -5; i <= 5; ++i)
    for (int j = -5; j <= 5; ++j) sheet.push_back({float(i * s), float(j * s), 0.f});
  const auto k = computeAnisotropicKernels(sheet, settings)[60];
  EXPECT_GT(k.metric[5], 4 * k.metric[0]) << "metric zz should dominate (short axis along z)";
  // A thin stream along x: long along x.
  test::Points line;
  for (int i = -10; i <= 10; ++i) line.push_back({float(i * s * 0.5), 0.f, 0.f});
  const auto l = computeAnisotropicKernels(line, settings)[10];
  EXPECT_LT(l.metric[0] * 4, l.metric[3]) << "metric xx should be smallest (long axis along x)";
}

/// 20,000 points, normally distributed with deviation `sigma` (times `zScale` along z): dense inside,
/// sparse outside, so both full and thin neighbourhoods occur.
test::Points gaussianBlob(unsigned seed, double sigma, double zScale) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, sigma);
  test::Points p;
  for (int n = 0; n < 20000; ++n) p.push_back({float(g(rng)), float(g(rng)), float(zScale * g(rng))});
  return p;
}

// The anisotropic kernels' neighbour sums and density splat built for AVX2 and for the baseline:
// identical kernels and level sets.
TEST(Anisotropic, Avx2AndBaselineKernelsAndDensityAreBitIdentical) {
  if (!simdSupported(SimdIsa::Avx2)) GTEST_SKIP() << "this CPU has no AVX2";
  const test::Points p = gaussianBlob(9, 0.1, 0.3);
  AnisotropicSettings settings;
  settings.spacing = 0.01;
  settings.support = 0.02;
  const auto base = computeAnisotropicKernels(p, settings, SimdIsa::Baseline);
  const auto avx2 = computeAnisotropicKernels(p, settings, SimdIsa::Avx2);
  ASSERT_EQ(base.size(), avx2.size());
  size_t stretched = 0;
  for (size_t i = 0; i < base.size(); ++i) {
    ASSERT_EQ(std::memcmp(&base[i], &avx2[i], sizeof base[i]), 0) << "kernel " << i;
    stretched += base[i].metric[0] != base[i].metric[3];
  }
  EXPECT_GT(stretched, 1000u);  // anisotropic kernels were compared, not only isolated spheres
  // The density splat's two builds, from these kernels: the same level set, bit for bit.
  const auto gridBase = rasterizeAnisotropic(base, 0.005, 3, {}, SimdIsa::Baseline);
  const auto gridAvx2 = rasterizeAnisotropic(base, 0.005, 3, {}, SimdIsa::Avx2);
  ASSERT_GT(gridBase->activeVoxelCount(), 10000u);
  ASSERT_EQ(gridBase->tree().leafCount(), gridAvx2->tree().leafCount());
  for (auto it = gridBase->tree().cbeginLeaf(); it; ++it) {
    const auto* other = gridAvx2->tree().probeConstLeaf(it->origin());
    ASSERT_NE(other, nullptr) << it->origin();
    EXPECT_TRUE(it->getValueMask() == other->getValueMask()) << it->origin();
    EXPECT_EQ(std::memcmp(it->buffer().data(), other->buffer().data(), sizeof(float) * it->SIZE), 0)
        << it->origin();
  }
}

// The block rasterizer against the Zhu-Bridson formula evaluated directly (doubles, every particle).
TEST(ZhuBridson, BlockRasterizerMatchesDirectEvaluation) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  test::Points p;
  for (int n = 0; n < 400; ++n) p.push_back({float(u(rng)), float(u(rng)), float(0.3 * u(rng))});
  const double voxel = 0.02, radius = 0.05, search = 0.1, halfWidth = 3;
  const auto grid = rasterizeZhuBridsonBlocks(p, voxel, radius, search, halfWidth);
  const float background = float(voxel * halfWidth);
  EXPECT_FLOAT_EQ(grid->background(), background);
  size_t checked = 0, active = 0;
  for (int i = -30; i <= 30; i += 3)
    for (int j = -30; j <= 30; j += 3)
      for (int k = -12; k <= 12; ++k) {
        const openvdb::Coord c(i, j, k);
        const double x[3] = {i * voxel, j * voxel, k * voxel};
        double w = 0, m[3] = {0, 0, 0};
        for (const auto& q : p) {
          const double d2 =
              (q[0] - x[0]) * (q[0] - x[0]) + (q[1] - x[1]) * (q[1] - x[1]) + (q[2] - x[2]) * (q[2] - x[2]);
          if (d2 >= search * search) continue;
          const double t = 1 - d2 / (search * search), kw = t * t * t;
          w += kw;
          for (int a = 0; a < 3; ++a) m[a] += kw * q[a];
        }
        const float got = grid->tree().getValue(c);
        ++checked;
        if (w == 0) {
          EXPECT_FLOAT_EQ(got, background) << c;
          continue;
        }
        const double e[3] = {x[0] - m[0] / w, x[1] - m[1] / w, x[2] - m[2] / w};
        const double phi = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) - radius;
        const double expected = std::clamp(phi, -double(background), double(background));
        EXPECT_NEAR(got, expected, 1e-4 * voxel + 1e-5 * std::abs(phi)) << c;
        EXPECT_EQ(grid->tree().isValueOn(c), std::abs(phi) < background) << c;
        active += std::abs(phi) < background;
      }
  EXPECT_GT(active, 200u);
  EXPECT_GT(checked, 5000u);
}

// The AVX2 splat and the baseline (SSE) splat round alike: identical grids, voxel for voxel and bit for
// bit, so a frame surfaces the same on every CPU.
TEST(ZhuBridson, Avx2AndBaselineSplatsAreBitIdentical) {
  if (!simdSupported(SimdIsa::Avx2)) GTEST_SKIP() << "this CPU has no AVX2";
  const test::Points p = gaussianBlob(5, 0.2, 0.5);
  const double voxel = 0.01, radius = 0.02, search = 0.04, halfWidth = 3;
  const auto base = rasterizeZhuBridsonBlocks(p, voxel, radius, search, halfWidth, SimdIsa::Baseline);
  const auto avx2 = rasterizeZhuBridsonBlocks(p, voxel, radius, search, halfWidth, SimdIsa::Avx2);
  ASSERT_EQ(base->tree().leafCount(), avx2->tree().leafCount());
  ASSERT_GT(base->tree().activeVoxelCount(), 10000u);
  size_t leaves = 0;
  for (auto it = base->tree().cbeginLeaf(); it; ++it, ++leaves) {
    const auto* other = avx2->tree().probeConstLeaf(it->origin());
    ASSERT_NE(other, nullptr) << it->origin();
    EXPECT_TRUE(it->getValueMask() == other->getValueMask()) << it->origin();
    EXPECT_EQ(std::memcmp(it->buffer().data(), other->buffer().data(), sizeof(float) * it->SIZE), 0)
        << it->origin();
  }
  EXPECT_EQ(leaves, base->tree().leafCount());
}

// The output band holds signed distances: next to the surface, phi(x) matches |x| - R for a ball, R
// taken from the mesh's volume, to half a voxel (the lattice bumps account for part of it). Not for
// `spheres`, whose surface keeps bumps of about a voxel over the lattice: a ball is no reference there.
TEST(LevelSet, BandHoldsSignedDistances) {
  for (auto method : {SurfaceMethod::ZhuBridson, SurfaceMethod::Anisotropic}) {
    const double s = 1.0 / 8;
    const SurfaceParams params = defaultParams(method, s);
    const auto grid = buildLevelSet(test::sphereLattice(1.0, s), params);
    const auto m = measure(meshLevelSet(*grid, 0));
    const double r = std::cbrt(3 * m.volume / (4 * std::numbers::pi));
    const double dx = params.voxelSize;
    EXPECT_NEAR(grid->background(), params.halfWidth * dx, 1e-6);
    double worst = 0, sumAll = 0;
    size_t n = 0, far = 0;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
      const auto x = grid->indexToWorld(it.getCoord());
      const double exact = x.length() - r;
      EXPECT_LT(std::abs(*it), grid->background() + 1e-6);
      sumAll += std::abs(*it - exact);
      far += std::abs(exact) > grid->background() + dx;
      if (std::abs(exact) > dx) continue;  // the voxels around the zero crossing
      worst = std::max(worst, std::abs(*it - exact));
      ++n;
    }
    const size_t active = grid->activeVoxelCount();
    std::printf(
        "%-12s band: %zu voxels within 1 voxel of the surface, worst |phi - distance| %.3f voxels; all %zu "
        "active: mean |phi - distance| %.3f voxels, %zu beyond half width + 1 voxel\n",
        methodName(method).c_str(), n, worst / dx, active, sumAll / double(active) / dx, far);
    EXPECT_GT(n, 1000u);
    EXPECT_LT(worst, 0.5 * dx) << methodName(method);
    // Deeper in the band the values converge more slowly (measured mean 0.21 voxels zhu-bridson, 0.16
    // anisotropic); no voxel far outside the band stays active.
    EXPECT_LT(sumAll / double(active), 0.3 * dx) << methodName(method);
    EXPECT_EQ(far, 0u) << methodName(method);
  }
}

// The anisotropic band's distances (group-marched Eikonal updates) from a field that is not a distance,
// f = |x|^2 - R^2, against the exact |x| - R, and against OpenVDB's fast sweeping from the same field.
TEST(LevelSet, GroupMarchedBandDistancesMatchTheExactDistance) {
  const double voxel = 0.1, radius = 2.05;
  const int reach = int(std::ceil(radius / voxel)) + 6;
  auto field = openvdb::FloatGrid::create(1.f);  // outside
  field->setTransform(openvdb::math::Transform::createLinearTransform(voxel));
  auto acc = field->getAccessor();
  for (int i = -reach; i <= reach; ++i)
    for (int j = -reach; j <= reach; ++j)
      for (int k = -reach; k <= reach; ++k) {
        const double r = voxel * std::sqrt(double(i * i + j * j + k * k));
        const float f = float(r * r - radius * radius);
        // The band: within 4 voxels of the sphere; every other voxel of the leaves inactive, as in
        // rasterizeAnisotropic.
        if (std::abs(r - radius) <= 4 * voxel)
          acc.setValue(openvdb::Coord(i, j, k), f);
        else
          acc.setValueOff(openvdb::Coord(i, j, k), f);
      }
  const double halfWidth = 3;
  const auto ours = bandDistances(*field, halfWidth + 1);
  const auto sweeping = openvdb::tools::sdfToSdf(*field, 0.f, 1);
  struct Error {
    double worstNear = 0, sum = 0;
    size_t n = 0;
  };
  auto error = [&](const openvdb::FloatGrid& g) {
    Error e;
    auto a = g.getConstAccessor();
    for (auto it = field->cbeginValueOn(); it; ++it) {
      const auto x = field->indexToWorld(it.getCoord());
      const double exact = x.length() - radius;
      if (std::abs(exact) > halfWidth * voxel) continue;  // what the trim keeps
      const double d = std::abs(a.getValue(it.getCoord()) - exact) / voxel;
      e.sum += d;
      ++e.n;
      if (std::abs(exact) <= voxel) e.worstNear = std::max(e.worstNear, d);
    }
    return e;
  };
  const Error a = error(*ours), b = error(*sweeping);
  std::printf(
      "band distances (voxels): group marching worst near %.3f, mean %.3f; fast sweeping worst near %.3f, "
      "mean %.3f "
      "(%zu voxels)\n",
      a.worstNear, a.sum / double(a.n), b.worstNear, b.sum / double(b.n), a.n);
  ASSERT_GT(a.n, 10000u);
  // Near the surface both start from the same first-order crossing distances (measured 0.335 voxels
  // worst on this curved field); deeper, group marching measured mean 0.053 against sweeping's 0.051.
  EXPECT_LT(a.worstNear, 0.4);
  EXPECT_LE(a.worstNear, b.worstNear + 0.01);
  EXPECT_LT(a.sum / double(a.n), 0.07);
  EXPECT_LT(a.sum / double(a.n), 1.1 * b.sum / double(b.n) + 0.005);
}

TEST(LevelSet, EmptyInputGivesEmptyLevelSet) {
  const SurfaceParams params = defaultParams(SurfaceMethod::ZhuBridson, 0.1);
  const auto grid = buildLevelSet({}, params);
  EXPECT_EQ(grid->activeVoxelCount(), 0u);
  EXPECT_EQ(grid->getGridClass(), openvdb::GRID_LEVEL_SET);
  EXPECT_TRUE(meshLevelSet(*grid, 0).triangles.empty());
}

TEST(LevelSet, SmallRadiusIsWarnedNotDropped) {
  SurfaceParams params = defaultParams(SurfaceMethod::Spheres, 0.1);
  params.radius = 0.5 * params.voxelSize;
  params.calibrate = false;
  LevelSetReport report;
  const auto grid = buildLevelSet({{0, 0, 0}, {1, 0, 0}}, params, &report);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings[0].find("voxel"), std::string::npos);
  EXPECT_GT(grid->activeVoxelCount(), 0u) << "particles below OpenVDB's minimum radius were dropped";
}

}  // namespace
}  // namespace sphfx::surfacing
