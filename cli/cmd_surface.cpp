#include <fmt/format.h>

#include "commands.h"
#include "sphfx/core/error.h"
#include "sphfx/core/log.h"
#include "sphfx/surfacing/surfacing.h"

namespace sphfx::cli {

namespace {

struct SurfaceOptions {
  surfacing::SurfaceJob job;
  std::string method;
  double voxelSize = 0, radius = 0, adaptivity = 0;
  int smooth = 0;
};

}  // namespace

void addSurfaceCommand(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "surface", "Turn a shot's particle caches into level sets (SHOT/surface) and meshes (SHOT/mesh)");
  auto o = std::make_shared<SurfaceOptions>();
  cmd->add_option("SHOT", o->job.shotDir, "Shot directory (reads SHOT/cache/particles.####.vdb)")->required();
  cmd->add_option("--frames", o->job.frames,
                  "Frame range A-B or a single frame (default: every cached frame)");
  auto* method = cmd->add_option("--method", o->method,
                                 "Particle-to-level-set method (default: the scene's surface.method). " +
                                     methodDescriptions(surfacingMethodRegistry()));
  auto* voxel =
      cmd->add_option("--voxel-size", o->voxelSize, "Voxel size in m (default: 0.5 particle spacings)");
  auto* radius = cmd->add_option("--radius", o->radius, "Particle radius in m (default: 1 particle spacing)");
  auto* smooth = cmd->add_option("--smooth", o->smooth, "Mean-curvature smoothing iterations (default: 2)");
  auto* adapt = cmd->add_option("--adaptivity", o->adaptivity, "Mesh adaptivity in [0, 1] (default: 0)");
  auto* threads = cmd->add_option("--threads", o->job.threads, "Worker threads (default: all cores)");
  cmd->add_flag("--force", o->job.force, "Redo frames whose outputs are already newer than the cache");
  cmd->callback([o, method, voxel, radius, smooth, adapt, threads] {
    auto& ov = o->job.overrides;
    if (method->count()) ov.method = surfacing::parseMethod(o->method);
    if (voxel->count()) ov.voxelSize = o->voxelSize;
    if (radius->count()) ov.radius = o->radius;
    if (smooth->count()) ov.smoothIterations = o->smooth;
    if (adapt->count()) ov.adaptivity = o->adaptivity;
    if (threads->count() && o->job.threads < 1)
      throw InputError(fmt::format("surface: --threads must be 1 or more, got {}", o->job.threads));
    const auto run = surfacing::surfaceShot(o->job);
    size_t done = 0, triangles = 0;
    double seconds = 0;
    for (const auto& f : run.frames)
      if (!f.skipped) ++done, triangles += f.triangles, seconds += f.seconds;
    logInfo(fmt::format(
        "surface: {} frames surfaced ({} up to date) with {}, voxel {:.4g} m, {} triangles, {:.2f} "
        "s of frame time",
        done, run.frames.size() - done, surfacing::methodName(run.params.method), run.params.voxelSize,
        triangles, seconds));
  });
}

}  // namespace sphfx::cli
