// Particles to a smoothed narrow-band level set: the three rasterizers, filtering and the calibrated offset.
#include <fmt/format.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <mutex>
#include <string>

#include "anisotropic.h"
#include "face_neighbours.h"
#include "sphfx/core/error.h"
#include "sphfx/surfacing/surfacing.h"
#include "zhu_bridson.h"

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

/// Records the wall time since the last lap under `name` in `report` (if any).
class StageTimer {
 public:
  explicit StageTimer(LevelSetReport* report) : report_(report) {}
  void lap(const std::string& name) {
    const auto now = std::chrono::steady_clock::now();
    if (report_) report_->stageSeconds.emplace_back(name, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }

 private:
  LevelSetReport* report_;
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
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
                                         const SurfaceParams& params, double halfWidth,
                                         LevelSetReport* report) {
  const double radius = params.radius;
  auto grid = openvdb::createLevelSet<openvdb::FloatGrid>(params.voxelSize, halfWidth);
  const double radiusVoxels = radius / params.voxelSize;
  openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
  // OpenVDB silently skips particles below rMin (1.5 voxels) or above rMax; keep every particle instead.
  if (radiusVoxels < raster.getRmin()) raster.setRmin(radiusVoxels * 0.5);
  if (radiusVoxels > raster.getRmax()) raster.setRmax(radiusVoxels * 2);
  warnSmallRadius(params.radius, params.voxelSize, report);
  raster.rasterizeSpheres(ParticleList(p, radius), radius);
  raster.finalize(true);
  const size_t dropped = raster.getMinCount() + raster.getMaxCount();
  if (dropped > 0 && report)
    report->warnings.push_back(
        fmt::format("OpenVDB ignored {} of {} particles for their size", dropped, p.size()));
  return grid;
}

/// Yu-Turk kernels, their density and its narrow band, each step timed as "rasterize_<step>".
openvdb::FloatGrid::Ptr rasterizeYuTurk(const std::vector<std::array<float, 3>>& p,
                                        const SurfaceParams& params, double halfWidth, StageTimer& timer) {
  AnisotropicSettings settings;
  settings.spacing = params.particleSpacing > 0 ? params.particleSpacing : params.radius;
  settings.support = 2 * params.radius;
  settings.lambda = params.anisotropic.lambda;
  settings.maxStretch = params.anisotropic.maxStretch;
  settings.isolatedBelow = params.anisotropic.isolatedBelow;
  settings.isolatedScale = params.anisotropic.isolatedScale;
  const auto kernels = computeAnisotropicKernels(p, settings);
  timer.lap("rasterize_kernels");
  return rasterizeAnisotropic(kernels, params.voxelSize, halfWidth,
                              [&](const char* step) { timer.lap(fmt::format("rasterize_{}", step)); });
}

/// Deactivates (to +-background) the active voxels outside `width` edge-neighbour dilations (L-infinity
/// <= width and L1 <= 2 width, which holds the Euclidean ball of radius `width`) of a
/// zero crossing, i.e. from a voxel whose face neighbour has the other sign. Zhu-Bridson's field is
/// about -radius everywhere inside, so without this the whole interior would stay active.
void restrictToBand(openvdb::FloatGrid& grid, int width) {
  using MaskTree = openvdb::MaskTree;
  openvdb::tree::LeafManager<openvdb::FloatTree> leafs(grid.tree());
  std::vector<std::unique_ptr<MaskTree::LeafNodeType>> crossings(leafs.leafCount());
  leafs.foreach ([&](const openvdb::FloatTree::LeafNodeType& leaf, size_t idx) {
    const FaceNeighbours<openvdb::FloatTree> neighbour(grid.tree(), leaf);
    std::unique_ptr<MaskTree::LeafNodeType> mask;
    for (auto it = leaf.cbeginValueOn(); it; ++it) {
      const bool inside = *it < 0;
      const openvdb::Index n = it.pos();
      bool crossing = false;
      for (int a = 0; a < 3 && !crossing; ++a)
        for (int side = 0; side < 2 && !crossing; ++side) crossing = (neighbour(n, a, side) < 0) != inside;
      if (!crossing) continue;
      if (!mask) mask = std::make_unique<MaskTree::LeafNodeType>(leaf.origin(), false);
      mask->setValueOn(it.pos());
    }
    crossings[idx] = std::move(mask);
  });
  MaskTree band(false);
  for (auto& m : crossings)
    if (m) band.addLeaf(m.release());
  // Not the L-infinity cube: its corners (up to 5.2 voxels away at width 3) keep the plateau value -r,
  // which no trim removes and the renormalization takes several tracks to correct.
  openvdb::tools::dilateActiveValues(band, width, openvdb::tools::NN_FACE_EDGE, openvdb::tools::IGNORE_TILES);
  const float background = grid.background();
  leafs.foreach ([&](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
    const auto* keep = band.probeConstLeaf(leaf.origin());
    for (auto it = leaf.beginValueOn(); it; ++it)
      if (!keep || !keep->isValueOn(it.pos())) leaf.setValueOff(it.pos(), *it < 0 ? -background : background);
  });
  openvdb::tools::pruneLevelSet(grid.tree());
}

using LevelSetFilterT = openvdb::tools::LevelSetFilter<openvdb::FloatGrid>;

/// Adds `delta` to every active value: on distances, moves the surface by `delta` (positive erodes).
void addToActive(LevelSetFilterT& filter, float delta) {
  filter.leafs().foreach ([delta](openvdb::FloatTree::LeafNodeType& leaf, size_t) {
    for (auto it = leaf.beginValueOn(); it; ++it) it.setValue(*it + delta);
  });
}

/// Moves the surface of a band of distances by `offset` (world units; positive erodes), at most a
/// voxel: adds it, then refills the band's side the surface moved towards with one face-neighbour layer,
/// renormalizing only that layer, and trims the other side. The rest of the band still holds distances.
/// (OpenVDB's LevelSetFilter::offset takes half-voxel steps and renormalizes the whole band after each.)
void offsetDistances(LevelSetFilterT& filter, double offset) {
  addToActive(filter, float(offset));
  const openvdb::MaskTree before(filter.grid().tree(), false, openvdb::TopologyCopy());
  openvdb::tools::dilateActiveValues(filter.leafs(), 1, openvdb::tools::NN_FACE,
                                     openvdb::tools::IGNORE_TILES);
  openvdb::MaskTree added(filter.grid().tree(), false, openvdb::TopologyCopy());
  added.topologyDifference(before);
  filter.normalize(&added);
  filter.prune();
}

/// LevelSetTracker::track() (dilate the band by a voxel, renormalize, trim) with `offset`, at most a
/// voxel, added before the trim: the offset of a field that holds no distances yet, for the price of
/// the one renormalization it needs anyway.
void trackWithOffset(LevelSetFilterT& filter, double offset) {
  openvdb::tools::dilateActiveValues(filter.leafs(), 1, openvdb::tools::NN_FACE,
                                     openvdb::tools::IGNORE_TILES);
  filter.normalize();
  addToActive(filter, float(offset));
  filter.prune();
}

/// Mean-curvature smoothing and the calibrated offset with OpenVDB's LevelSetFilter, which
/// renormalizes and re-tracks the band after every step: renormalizing only at the end, or folding the
/// offset into the Zhu-Bridson radius, moves the surface by amounts the flat-slab calibration does not
/// see (the pool-top and sphere-convergence tests fail).
void smoothAndOffset(openvdb::FloatGrid& grid, int iterations, double offset, bool holdsDistances,
                     StageTimer& timer) {
  if (iterations <= 0 && offset == 0) return;
  LevelSetFilterT filter(grid);
  // First-order upwinding for the renormalization after each step: the default fifth-order WENO
  // scheme costs several times more. Three renormalization sweeps (OpenVDB's default) are kept: with
  // one, the sphere test's volume error no longer falls as the resolution rises.
  filter.setSpatialScheme(openvdb::math::FIRST_BIAS);
  filter.setTemporalScheme(openvdb::math::TVD_RK1);
  filter.setNormCount(3);
  // Mean curvature flow: removes the particle bumps without moving flat regions.
  for (int i = 0; i < iterations; ++i) filter.meanCurvature();
  timer.lap("smooth");
  // The offset assumes distances. Without smoothing only the anisotropic band holds them: Zhu-Bridson's
  // field levels off at -r inside and a union of spheres is shallow between the spheres, so adding the
  // offset to them erodes thin sheets into droplets and opens pits in a flat pool (measured: the pool
  // top 0.79 s low, RMS 0.70 s; renormalized first, 0.014 s low, RMS 0.052 s).
  const bool rawField = iterations == 0 && !holdsDistances;
  const double voxel = filter.voxelSize();
  const int steps = int(std::ceil(std::abs(offset) / voxel - 1e-6));
  for (int i = 0; i < steps; ++i) {
    if (i == 0 && rawField)
      trackWithOffset(filter, offset / steps);
    else
      offsetDistances(filter, offset / steps);
  }
  timer.lap("offset");
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
  StageTimer timer(report);
  openvdb::FloatGrid::Ptr grid;
  if (positions.empty()) {
    grid = openvdb::createLevelSet<openvdb::FloatGrid>(params.voxelSize, params.halfWidth);
  } else {
    switch (params.method) {
      case SurfaceMethod::Spheres:
        grid = rasterizeSpheres(positions, params, params.halfWidth, report);
        break;
      case SurfaceMethod::ZhuBridson:
        warnSmallRadius(params.radius, params.voxelSize, report);
        grid = rasterizeZhuBridsonBlocks(positions, params.voxelSize, params.radius, 2 * params.radius,
                                         params.halfWidth);
        timer.lap("rasterize_splat");
        // Its field is about -r everywhere inside, within the band: keep only the zero crossing's
        // neighbourhood, or the filter below processes the whole interior.
        restrictToBand(*grid, int(std::ceil(params.halfWidth)));
        timer.lap("rasterize_band");
        break;
      case SurfaceMethod::Anisotropic:
        grid = rasterizeYuTurk(positions, params, params.halfWidth, timer);
        break;
    }
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    if (params.method == SurfaceMethod::Spheres) timer.lap("rasterize");
    smoothAndOffset(*grid, params.smoothIterations, params.calibrate ? params.surfaceOffset : 0.0,
                    params.method == SurfaceMethod::Anisotropic, timer);
    openvdb::tools::pruneLevelSet(grid->tree());
    timer.lap("prune");
  }
  grid->setName("surface");
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

namespace {

/// Height of a flat lattice face surfaced with `params`, minus where it should be (half a spacing
/// beyond the outer particles); NaN if the spacing is unknown or no crossing was found.
double slabTopError(const SurfaceParams& params) {
  const double s = params.particleSpacing;
  if (!(s > 0)) return std::nan("");
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
  const auto grid = buildLevelSet(lattice, params, nullptr);
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
  if (count == 0) return std::nan("");
  return sum / count - 0.5 * s;
}

}  // namespace

double calibrateOffset(const SurfaceParams& params) {
  SurfaceParams uncalibrated = params;
  uncalibrated.calibrate = false;
  uncalibrated.surfaceOffset = 0;
  const double first = slabTopError(uncalibrated);
  if (!std::isfinite(first)) return 0;
  return first;
}

}  // namespace sphfx::surfacing
