// Particles to a smoothed narrow-band level set: the three rasterizers, filtering and the calibrated offset.
#include <fmt/format.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointRasterizeSDF.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tools/Prune.h>

#include <cmath>
#include <mutex>

#include "sphfx/core/error.h"
#include "sphfx/surfacing/anisotropic.h"
#include "sphfx/surfacing/surfacing.h"

namespace sphfx::surfacing {
namespace {

// Radius, in voxels, below which ParticlesToLevelSet skips a particle by default (its rMin).
constexpr double kMinRadiusVoxels = 1.5;

/// ParticlesToLevelSet's particle list concept over our positions, with one radius for all.
class ParticleList {
 public:
  using PosType = openvdb::Vec3R;
  ParticleList(const std::vector<std::array<float, 3>>& p, double radius) : p_(p), radius_(radius) {}
  size_t size() const { return p_.size(); }
  void getPos(size_t n, openvdb::Vec3R& xyz) const { xyz = openvdb::Vec3R(p_[n][0], p_[n][1], p_[n][2]); }
  void getPosRad(size_t n, openvdb::Vec3R& xyz, openvdb::Real& rad) const {
    getPos(n, xyz);
    rad = radius_;
  }

 private:
  const std::vector<std::array<float, 3>>& p_;
  double radius_;
};

void initOpenVdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

void warnSmallRadius(double radius, double voxel, LevelSetReport* report) {
  if (radius / voxel >= kMinRadiusVoxels || !report) return;
  report->warnings.push_back(fmt::format(
      "particle radius {:.4g} m is {:.2f} voxels, below OpenVDB's {} voxel minimum: the particles are kept, "
      "but the surface aliases; use --voxel-size below {:.4g}",
      radius, radius / voxel, kMinRadiusVoxels, radius / kMinRadiusVoxels));
}

openvdb::FloatGrid::Ptr rasterizeSpheres(const std::vector<std::array<float, 3>>& p,
                                         const SurfaceParams& params, LevelSetReport* report) {
  auto grid = openvdb::createLevelSet<openvdb::FloatGrid>(params.voxelSize, params.halfWidth);
  const double radiusVoxels = params.radius / params.voxelSize;
  openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
  // OpenVDB silently skips particles below rMin (1.5 voxels) or above rMax; keep every particle instead.
  if (radiusVoxels < raster.getRmin()) raster.setRmin(radiusVoxels * 0.5);
  if (radiusVoxels > raster.getRmax()) raster.setRmax(radiusVoxels * 2);
  warnSmallRadius(params.radius, params.voxelSize, report);
  raster.rasterizeSpheres(ParticleList(p, params.radius), params.radius);
  raster.finalize(true);
  const size_t dropped = raster.getMinCount() + raster.getMaxCount();
  if (dropped > 0 && report)
    report->warnings.push_back(
        fmt::format("OpenVDB ignored {} of {} particles for their size", dropped, p.size()));
  return grid;
}

openvdb::points::PointDataGrid::Ptr toPointDataGrid(const std::vector<std::array<float, 3>>& p,
                                                    double voxel) {
  std::vector<openvdb::Vec3R> positions(p.size());
  for (size_t i = 0; i < p.size(); ++i) positions[i] = openvdb::Vec3R(p[i][0], p[i][1], p[i][2]);
  auto transform = openvdb::math::Transform::createLinearTransform(voxel);
  return openvdb::points::createPointDataGrid<openvdb::points::NullCodec, openvdb::points::PointDataGrid>(
      positions, *transform);
}

openvdb::FloatGrid::Ptr rasterizeZhuBridson(const std::vector<std::array<float, 3>>& p,
                                            const SurfaceParams& params, LevelSetReport* report) {
  warnSmallRadius(params.radius, params.voxelSize, report);
  // Zhu & Bridson's kernel reaches twice the particle radius: neighbours blend without swelling the surface.
  const double search = 2 * params.radius;
  const auto points = toPointDataGrid(p, search);
  auto transform = openvdb::math::Transform::createLinearTransform(params.voxelSize);
  auto grid =
      openvdb::points::rasterizeSmoothSpheres(*points, params.radius, search, params.halfWidth, transform);
  return grid;
}

openvdb::FloatGrid::Ptr rasterizeYuTurk(const std::vector<std::array<float, 3>>& p,
                                        const SurfaceParams& params) {
  AnisotropicSettings settings;
  settings.spacing = params.particleSpacing > 0 ? params.particleSpacing : params.radius;
  settings.support = 2 * params.radius;
  const auto kernels = computeAnisotropicKernels(p, settings);
  return rasterizeAnisotropic(kernels, params.voxelSize, params.halfWidth);
}

void checkParams(const SurfaceParams& params) {
  auto good = [](double v) { return std::isfinite(v) && v > 0; };
  if (!good(params.voxelSize) || !good(params.radius) || !good(params.halfWidth) ||
      params.smoothIterations < 0 || !(params.adaptivity >= 0 && params.adaptivity <= 1) ||
      !std::isfinite(params.surfaceOffset))
    throw InputError(
        fmt::format("surfacing: invalid parameters (voxel size {}, radius {}, smoothing {}, adaptivity {})",
                    params.voxelSize, params.radius, params.smoothIterations, params.adaptivity));
}

/// Height of the zero crossing above `zFrom` at (x, y), marching upward from inside.
double crossingHeight(const openvdb::FloatGrid& grid, double x, double y, double zFrom, double zTo) {
  openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(grid);
  const double step = grid.voxelSize()[0] / 16;
  double zPrev = zFrom, vPrev = sampler.wsSample(openvdb::Vec3R(x, y, zFrom));
  for (double z = zFrom + step; z <= zTo; z += step) {
    const double v = sampler.wsSample(openvdb::Vec3R(x, y, z));
    if (vPrev < 0 && v >= 0) return zPrev + (z - zPrev) * (-vPrev) / (v - vPrev);
    zPrev = z;
    vPrev = v;
  }
  return std::nan("");
}

}  // namespace

openvdb::FloatGrid::Ptr buildLevelSet(const std::vector<std::array<float, 3>>& positions,
                                      const SurfaceParams& params, LevelSetReport* report) {
  initOpenVdb();
  checkParams(params);
  openvdb::FloatGrid::Ptr grid;
  if (positions.empty()) {
    grid = openvdb::createLevelSet<openvdb::FloatGrid>(params.voxelSize, params.halfWidth);
  } else {
    switch (params.method) {
      case SurfaceMethod::Spheres:
        grid = rasterizeSpheres(positions, params, report);
        break;
      case SurfaceMethod::ZhuBridson:
        grid = rasterizeZhuBridson(positions, params, report);
        break;
      case SurfaceMethod::Anisotropic:
        grid = rasterizeYuTurk(positions, params);
        break;
    }
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    const double offset = params.calibrate ? params.surfaceOffset : 0.0;
    if (params.smoothIterations > 0 || offset != 0) {
      openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*grid);
      // First-order upwinding for the renormalization after each step: the default fifth-order WENO
      // scheme costs several times more. Three renormalization sweeps (OpenVDB's default) are kept: with
      // one, the sphere test's volume error no longer falls as the resolution rises.
      filter.setSpatialScheme(openvdb::math::FIRST_BIAS);
      filter.setTemporalScheme(openvdb::math::TVD_RK1);
      filter.setNormCount(3);
      // Mean curvature flow: removes the particle bumps without moving flat regions.
      for (int i = 0; i < params.smoothIterations; ++i) filter.meanCurvature();
      if (offset != 0) filter.offset(float(offset));
    }
    openvdb::tools::pruneLevelSet(grid->tree());
  }
  grid->setName("surface");
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

double calibrateOffset(const SurfaceParams& params) {
  const double s = params.particleSpacing;
  if (!(s > 0)) return 0;
  // A slab wide enough that its sides do not reach the centre column: kernel reach, smoothing spread
  // (about a voxel per iteration) and the band.
  const double reach =
      4 * params.radius + (params.smoothIterations + params.halfWidth + 2) * params.voxelSize;
  const int half = std::min(40, int(std::ceil(reach / s)) + 1);
  const int width = 2 * half + 1, depth = half + 1;
  std::vector<std::array<float, 3>> lattice;
  lattice.reserve(size_t(width) * width * depth);
  for (int i = 0; i < width; ++i)
    for (int j = 0; j < width; ++j)
      for (int k = 0; k < depth; ++k)
        lattice.push_back({float((i - half) * s), float((j - half) * s), float(k * s)});
  SurfaceParams uncalibrated = params;
  uncalibrated.calibrate = false;
  const auto grid = buildLevelSet(lattice, uncalibrated, nullptr);
  // Average the surface height over one lattice period around the centre particle.
  const double top = (depth - 1) * s;
  constexpr int kSamples = 8;
  double sum = 0;
  int count = 0;
  for (int a = 0; a < kSamples; ++a)
    for (int b = 0; b < kSamples; ++b) {
      const double x = ((a + 0.5) / kSamples - 0.5) * s, y = ((b + 0.5) / kSamples - 0.5) * s;
      const double z = crossingHeight(*grid, x, y, top - s, top + 4 * params.radius + 2 * s);
      if (std::isfinite(z)) {
        sum += z - top;
        ++count;
      }
    }
  if (count == 0) return 0;
  return sum / count - 0.5 * s;
}

}  // namespace sphfx::surfacing
