#pragma once
/// @file surfacing.h
/// @brief The surfacing stage: particle caches (SHOT/cache/particles.####.vdb) to narrow-band level sets
/// (SHOT/surface/surface.####.vdb) and triangle meshes (SHOT/mesh/mesh.####.ply).
///
/// Pipeline per frame: rasterize the particles with one of three methods (union of spheres, Zhu-Bridson
/// smooth spheres, Yu-Turk anisotropic kernels), smooth the level set (mean curvature flow), shift it by a
/// calibrated offset so that a flat lattice face sits half a spacing beyond its outer particles (each
/// particle then encloses one spacing cubed), mesh it with openvdb::tools::volumeToMesh.

#include <openvdb/openvdb.h>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sphfx/core/frame_files.h"
#include "sphfx/core/mesh_io.h"
#include "sphfx/core/scene.h"

namespace sphfx::surfacing {

/// Resolved surfacing parameters, all lengths in metres.
struct SurfaceParams {
  SurfaceMethod method = SurfaceMethod::ZhuBridson;
  double particleSpacing = 0;  ///< the cache's spacing; the calibration lattice uses it
  double voxelSize = 0;
  double radius = 0;  ///< particle radius (spheres, zhu-bridson) or half the kernel support (anisotropic)
  int smoothIterations = 0;                ///< mean-curvature iterations
  double adaptivity = 0;                   ///< volumeToMesh adaptivity in [0, 1]
  bool calibrate = true;                   ///< apply surfaceOffset (see calibrateOffset())
  double surfaceOffset = 0;                ///< erosion (m) applied after smoothing, from calibrateOffset()
  double halfWidth = 3;                    ///< narrow band half width in voxels
  AnisotropicSurfaceSettings anisotropic;  ///< the anisotropic method's kernel parameters
};

/// Values the user gave on the command line; they win over the scene's (and its defaults).
struct SurfaceOverrides {
  std::optional<SurfaceMethod> method;
  std::optional<double> voxelSize;
  std::optional<double> radius;
  std::optional<int> smoothIterations;
  std::optional<double> adaptivity;
};

/// The method's registry name (sphfx/core/methods.h).
std::string methodName(SurfaceMethod method);
/// The registered method names, for CLI help and checks.
std::vector<std::string> methodNames();
/// @throws InputError for a name the registry lacks (lists the valid ones).
SurfaceMethod parseMethod(const std::string& name);

/// Resolves parameters: `overrides` first, then `settings` (factors of `spacing`). Does not calibrate.
/// @throws InputError if a value is out of range (voxel size or radius not positive and finite, smoothing
/// negative, adaptivity outside [0, 1]) or if `spacing` is unknown (<= 0) and no voxel size and radius
/// were given.
SurfaceParams resolveParams(double spacing, const SurfaceSettings& settings,
                            const SurfaceOverrides& overrides);

/// The erosion (m) that moves the surface of a flat face of a cubic lattice of `params.particleSpacing`
/// to half a spacing beyond its outer particles, measured by surfacing a small lattice slab with `params`
/// (calibration off). Deterministic. Returns 0 when the spacing is unknown.
double calibrateOffset(const SurfaceParams& params);

/// What happened while building one level set.
struct LevelSetReport {
  std::vector<std::string> warnings;  ///< e.g. particles OpenVDB would have dropped, and what was done
  std::vector<std::pair<std::string, double>> stageSeconds;  ///< wall time of each step, in order
};

/// Builds the narrow-band level set (FloatGrid, class GRID_LEVEL_SET, name "surface") of `positions`:
/// rasterize, smooth, offset by params.surfaceOffset when params.calibrate. Deterministic for any
/// number of TBB threads. An empty input gives an empty level set.
/// @throws InputError if the parameters are not positive and finite.
openvdb::FloatGrid::Ptr buildLevelSet(const std::vector<std::array<float, 3>>& positions,
                                      const SurfaceParams& params, LevelSetReport* report = nullptr);

/// The zero isosurface of a level set as triangles (quads split along their shorter diagonal), with
/// outward vertex normals from the level set's gradient. Deterministic.
TriangleMesh meshLevelSet(const openvdb::FloatGrid& grid, double adaptivity);

/// Writes `grid` to `path` atomically (Blosc or Zip compressed). The archive UUID that OpenVDB draws at
/// random for every write is replaced by one derived from the file's contents, so that the same grid
/// always gives the same bytes.
/// @throws IoError if the file cannot be written.
void writeLevelSet(const std::string& path, const openvdb::FloatGrid& grid);

/// Figures for one frame.
struct FrameStats {
  int frame = 0;
  bool skipped = false;  ///< outputs were already newer than the cache
  double seconds = 0;
  size_t particles = 0;
  uint64_t activeVoxels = 0;
  size_t vertices = 0;
  size_t triangles = 0;
  std::vector<std::pair<std::string, double>> stageSeconds;  ///< wall time of each step (not in manifest)
};

/// Surfaces one particle frame: reads `cachePath`, writes the level set and the mesh atomically.
/// @throws InputError for a cache that is not an sphfx cache; IoError on read/write failures.
FrameStats surfaceFrame(const std::string& cachePath, const std::string& surfacePath,
                        const std::string& meshPath, const SurfaceParams& params);

/// One `sphfx surface` run.
struct SurfaceJob {
  std::string shotDir;
  std::string frames;  ///< "A-B" or "A"; empty: every cached frame
  SurfaceOverrides overrides;
  int threads = 0;     ///< 0: all cores
  bool force = false;  ///< redo frames whose outputs are already newer than the cache
};

struct SurfaceRunReport {
  SurfaceParams params;
  std::vector<FrameStats> frames;  ///< in frame order
};

/// Surfaces the frames of a shot in parallel (TBB, at most job.threads threads), with a progress line,
/// and records the parameters and per-frame figures in the manifest's "surface" section. Frames whose
/// outputs are newer than their cache and were made with the same parameters are skipped unless
/// job.force. Parameters: job.overrides, then the manifest's "simulate.scene" surface settings, then the
/// scene defaults, scaled by the cache's particle spacing.
/// @throws InputError for a missing shot, no cache frames (in the range), a bad range or bad options;
/// IoError on read/write failures.
SurfaceRunReport surfaceShot(const SurfaceJob& job);

}  // namespace sphfx::surfacing
