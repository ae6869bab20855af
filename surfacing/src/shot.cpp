// One frame and one shot: cache in, level set and mesh out, figures into the manifest.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <openvdb/io/File.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>

#include "sphfx/core/error.h"
#include "sphfx/core/log.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/surfacing/surfacing.h"

namespace fs = std::filesystem;

namespace sphfx::surfacing {
namespace {

void checkPositive(const char* option, double v) {
  if (!(std::isfinite(v) && v > 0))
    throw InputError(fmt::format("surface: {} must be a positive length in metres, got {}", option, v));
}

/// The particle spacing stored in a cache file's grid metadata (reads no points).
double cacheSpacing(const std::string& path) {
  openvdb::initialize();
  try {
    openvdb::io::File file(path);
    file.open(false);
    const auto grids = file.readAllGridMetadata();
    file.close();
    for (const auto& g : *grids)
      if (g->getName() == "points")
        if (auto m = g->getMetadata<openvdb::DoubleMetadata>("particle_spacing")) return m->value();
  } catch (const openvdb::Exception& e) {
    throw InputError(path + ": not a readable OpenVDB file: " + e.what());
  }
  throw InputError(path + ": not an sphfx particle cache (no \"points\" grid with \"particle_spacing\")");
}

/// The scene's surface settings from the manifest, else the scene defaults.
SurfaceSettings sceneSurfaceSettings(const std::string& shotDir) {
  const ManifestJson m = readManifest(shotDir);
  if (m.contains("simulate") && m["simulate"].contains("scene")) {
    const schema::Json raw = schema::Json::parse(m["simulate"]["scene"].dump());
    return parseScene(raw, manifestPath(shotDir) + " (simulate.scene)").surface;
  }
  Scene scene;
  sceneSchema().setDefaults(scene);
  return scene.surface;
}

ManifestJson paramsJson(const SurfaceParams& p) {
  return ManifestJson{{"method", methodName(p.method)},
                      {"particle_spacing", p.particleSpacing},
                      {"voxel_size", p.voxelSize},
                      {"radius", p.radius},
                      {"smooth_iterations", p.smoothIterations},
                      {"adaptivity", p.adaptivity},
                      {"surface_offset", p.calibrate ? p.surfaceOffset : 0.0}};
}

bool newerThan(const std::string& output, const fs::file_time_type& input) {
  std::error_code ec;
  const auto t = fs::last_write_time(output, ec);
  return !ec && t >= input;
}

ManifestJson statsJson(const FrameStats& s) {
  return ManifestJson{{"seconds", std::round(s.seconds * 1000) / 1000},
                      {"particles", s.particles},
                      {"active_voxels", s.activeVoxels},
                      {"vertices", s.vertices},
                      {"triangles", s.triangles}};
}

std::vector<int> selectFrames(const std::string& shotDir, const std::string& rangeText) {
  std::error_code ec;
  if (!fs::is_directory(shotDir, ec)) throw InputError("surface: " + shotDir + ": no such shot directory");
  const std::string cacheDir = (fs::path(shotDir) / "cache").string();
  const std::vector<int> all = listFrames(cacheDir, "particles", "vdb");
  if (all.empty())
    throw InputError("surface: " + cacheDir + ": no particle cache frames (particles.####.vdb)");
  if (rangeText.empty()) return all;
  const FrameRange within{all.front(), all.back()};
  const FrameRange range = parseFrameRange(rangeText, &within);
  std::vector<int> out;
  for (int f : all)
    if (range.contains(f)) out.push_back(f);
  if (out.empty())
    throw InputError(fmt::format("surface: --frames {}: no cached frame in that range", rangeText));
  return out;
}

}  // namespace

std::string methodName(SurfaceMethod method) {
  return methodEntry(surfacingMethodRegistry(), method).name;
}

std::vector<std::string> methodNames() {
  return sphfx::methodNames(surfacingMethodRegistry());
}

SurfaceMethod parseMethod(const std::string& name) {
  for (const auto& e : surfacingMethodRegistry())
    if (e.name == name) return e.id;
  throw InputError(
      fmt::format("surface: --method: expected one of {}, got \"{}\"", fmt::join(methodNames(), ", "), name));
}

SurfaceParams resolveParams(double spacing, const SurfaceSettings& settings, const SurfaceOverrides& o) {
  if (o.voxelSize) checkPositive("--voxel-size", *o.voxelSize);
  if (o.radius) checkPositive("--radius", *o.radius);
  if (o.smoothIterations && *o.smoothIterations < 0)
    throw InputError(
        fmt::format("surface: --smooth must be 0 or more iterations, got {}", *o.smoothIterations));
  if (o.adaptivity && !(*o.adaptivity >= 0 && *o.adaptivity <= 1))
    throw InputError(fmt::format("surface: --adaptivity must be in [0, 1], got {}", *o.adaptivity));
  const bool known = std::isfinite(spacing) && spacing > 0;
  if (!known && (!o.voxelSize || !o.radius))
    throw InputError("surface: the cache has no particle spacing; give --voxel-size and --radius");
  SurfaceParams p;
  p.method = o.method.value_or(settings.method);
  p.particleSpacing = known ? spacing : 0;
  p.voxelSize = o.voxelSize.value_or(settings.voxelFactor * spacing);
  p.radius = o.radius.value_or(settings.radiusFactor * spacing);
  p.smoothIterations = o.smoothIterations.value_or(settings.smoothIterations);
  p.adaptivity = o.adaptivity.value_or(settings.adaptivity);
  p.anisotropic = settings.anisotropic;
  return p;
}

FrameStats surfaceFrame(const std::string& cachePath, const std::string& surfaceFile,
                        const std::string& meshFile, const SurfaceParams& params) {
  const auto start = std::chrono::steady_clock::now();
  auto lap = start;
  FrameStats s;
  auto timeStage = [&](const char* name) {
    const auto now = std::chrono::steady_clock::now();
    s.stageSeconds.emplace_back(name, std::chrono::duration<double>(now - lap).count());
    lap = now;
  };
  const ParticleFrame particles = readParticleCache(cachePath, CacheFields::Positions);
  timeStage("read");
  LevelSetReport report;
  auto grid = buildLevelSet(particles.position, params, &report);
  s.stageSeconds.insert(s.stageSeconds.end(), report.stageSeconds.begin(), report.stageSeconds.end());
  lap = std::chrono::steady_clock::now();
  for (const auto& w : report.warnings) logWarning(cachePath + ": " + w);
  grid->insertMeta("frame", openvdb::Int32Metadata(particles.frame));
  grid->insertMeta("sphfx_surface_method", openvdb::StringMetadata(methodName(params.method)));
  grid->insertMeta("particle_spacing", openvdb::DoubleMetadata(params.particleSpacing));
  // The VDB write (one thread: OpenVDB compresses leaf by leaf) overlaps the meshing and the PLY write;
  // both only read the grid. On unwinding, the task group waits for the write before `grid` goes.
  double vdbSeconds = 0;
  tbb::task_group vdbWrite;
  vdbWrite.run([&] {
    const auto t0 = std::chrono::steady_clock::now();
    writeLevelSet(surfaceFile, *grid);
    vdbSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  });
  const TriangleMesh mesh = meshLevelSet(*grid, params.adaptivity);
  timeStage("mesh");
  writePly(meshFile, mesh);
  timeStage("write_ply");
  vdbWrite.wait();
  timeStage("wait_vdb");
  s.stageSeconds.emplace_back("write_vdb_overlapped", vdbSeconds);
  s.frame = particles.frame;
  s.particles = particles.size();
  s.activeVoxels = grid->activeVoxelCount();
  s.vertices = mesh.positions.size();
  s.triangles = mesh.triangles.size();
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

SurfaceRunReport surfaceShot(const SurfaceJob& job) {
  if (job.threads < 0)
    throw InputError(fmt::format("surface: --threads must be 1 or more, got {}", job.threads));
  const std::vector<int> frames = selectFrames(job.shotDir, job.frames);
  const double spacing = cacheSpacing(particleCachePath(job.shotDir, frames.front()));
  SurfaceRunReport run;
  run.params = resolveParams(spacing, sceneSurfaceSettings(job.shotDir), job.overrides);
  std::unique_ptr<tbb::global_control> limit;
  if (job.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  size_t(job.threads));
  run.params.surfaceOffset = calibrateOffset(run.params);
  logVerbose(fmt::format("surface: {} voxel {:.4g} m radius {:.4g} m smoothing {} calibrated offset {:.4g} m",
                         methodName(run.params.method), run.params.voxelSize, run.params.radius,
                         run.params.smoothIterations, run.params.surfaceOffset));

  // Outputs made with other parameters are stale whatever their time stamps.
  const ManifestJson params = paramsJson(run.params);
  const ManifestJson before = readManifest(job.shotDir);
  const bool sameParams =
      before.contains("surface") && before["surface"].value("params", ManifestJson()) == params;
  updateManifest(job.shotDir, [&](ManifestJson& m) {
    // Decided again under the lock: another process (a farm task of another chunk) may have reset the
    // section to these parameters since `before` was read, and resetting it again would drop its frames.
    if (!m.contains("surface") || m["surface"].value("params", ManifestJson()) != params)
      m["surface"] = ManifestJson::object();
    m["surface"]["params"] = params;
    if (!m["surface"].contains("frames")) m["surface"]["frames"] = ManifestJson::object();
  });

  run.frames.resize(frames.size());
  std::mutex mutex;
  Progress progress("surface", int64_t(frames.size()));
  size_t done = 0;
  tbb::parallel_for(size_t(0), frames.size(), [&](size_t i) {
    const int f = frames[i];
    const std::string cache = particleCachePath(job.shotDir, f);
    const std::string surf = surfacePath(job.shotDir, f), mesh = meshPath(job.shotDir, f);
    const auto cacheTime = fs::last_write_time(cache);
    FrameStats s;
    if (!job.force && sameParams && newerThan(surf, cacheTime) && newerThan(mesh, cacheTime)) {
      s.frame = f;
      s.skipped = true;
    } else {
      s = surfaceFrame(cache, surf, mesh, run.params);
      s.frame = f;
      updateManifest(job.shotDir,
                     [&](ManifestJson& m) { m["surface"]["frames"][std::to_string(f)] = statsJson(s); });
    }
    std::lock_guard lock(mutex);
    run.frames[i] = s;
    progress.update(int64_t(++done), fmt::format("frame {}{}", f, s.skipped ? " (up to date)" : ""));
  });
  progress.finish();
  // Frames in numeric order, whatever order they finished in.
  updateManifest(job.shotDir, [&](ManifestJson& m) {
    std::map<int, ManifestJson> sorted;
    for (auto& [k, v] : m["surface"]["frames"].items()) sorted[std::stoi(k)] = v;
    ManifestJson ordered = ManifestJson::object();
    for (auto& [k, v] : sorted) ordered[std::to_string(k)] = v;
    m["surface"]["frames"] = ordered;
  });
  return run;
}

}  // namespace sphfx::surfacing
