#include "sphfx/sim/simulation.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "cache_writer.h"
#include "restart_file.h"
#include "sphfx/core/error.h"
#include "sphfx/core/log.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/gpu/gl.h"

namespace sphfx::sim {
namespace {

ManifestJson frameJson(const FrameStats& f) {
  ManifestJson j = ManifestJson::object();
  j["frame"] = f.frame;
  j["substeps"] = f.substeps;
  j["dt_min"] = f.dtMin;
  j["dt_mean"] = f.dtMean;
  j["dt_max"] = f.dtMax;
  j["wall_seconds"] = f.wallSeconds;
  if (f.particles >= 0) j["particles"] = f.particles;
  for (const auto& [key, value] : f.solverStats) j[key] = value;
  if (!f.warnings.empty()) j["warnings"] = f.warnings;
  return j;
}

// Keeps the per-frame entries of frames up to `last` (a resumed run replaces what follows).
void trimFrames(ManifestJson& section, int last) {
  ManifestJson kept = ManifestJson::array();
  if (section.contains("per_frame"))
    for (const auto& f : section["per_frame"])
      if (f["frame"].get<int>() <= last) kept.push_back(f);
  section["per_frame"] = kept;
}

void summarise(ManifestJson& section) {
  double lo = 0, hi = 0, sum = 0;
  int64_t steps = 0;
  int written = 0;
  for (const auto& f : section["per_frame"]) {
    const int n = f["substeps"].get<int>();
    written += f.value("written", false) ? 1 : 0;
    if (n == 0) continue;  // the initial frame
    lo = steps == 0 ? f["dt_min"].get<double>() : std::min(lo, f["dt_min"].get<double>());
    hi = std::max(hi, f["dt_max"].get<double>());
    sum += f["dt_mean"].get<double>() * n;
    steps += n;
  }
  section["frames_written"] = written;
  section["substeps"] = steps;
  ManifestJson dt = ManifestJson::object();
  dt["min"] = lo;
  dt["mean"] = steps ? sum / double(steps) : 0.0;
  dt["max"] = hi;
  section["dt"] = dt;
}

FrameRange writtenRange(const Scene& scene, const SimulationOptions& o) {
  const FrameRange all{scene.time.startFrame, scene.time.endFrame};
  if (!o.frames) return all;
  if (!all.contains(o.frames->first) || !all.contains(o.frames->last))
    throw InputError(fmt::format("--frames {}-{}: outside the scene's frames {}-{}", o.frames->first,
                                 o.frames->last, all.first, all.last));
  return *o.frames;
}

// Restores the latest restart file; returns the frame it holds, or nothing for a fresh start.
std::optional<int> resume(Simulator& sim, const Scene& scene, const std::string& shot, uint64_t hash) {
  const std::optional<int> frame = latestRestartFrame(shot);
  if (!frame) {
    logWarning("--resume: no restart file in " + shot + "/cache; starting from the first frame");
    return std::nullopt;
  }
  if (*frame < scene.time.startFrame || *frame > scene.time.endFrame)
    throw InputError(fmt::format("--resume: restart frame {} is outside the scene's frames", *frame));
  sim.restoreState(readRestartFile(restartPath(shot, *frame), hash));
  logInfo(fmt::format("resuming after frame {}", *frame));
  return frame;
}

}  // namespace

SimulationResult simulateShot(const Scene& scene, const SimulationOptions& o) {
  const auto wall0 = std::chrono::steady_clock::now();
  const FrameRange write = writtenRange(scene, o);
  const uint64_t hash = sceneStateHash(scene);
  std::filesystem::create_directories(std::filesystem::path(o.shotDir) / "cache");
  Simulator sim(scene, o.shotDir);
  SimulationResult result;
  result.particles = sim.particleCount();
  result.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  std::optional<int> resumed;
  if (o.resume) resumed = resume(sim, scene, o.shotDir, hash);
  result.resumedFrom = resumed.value_or(0);

  updateManifest(o.shotDir, [&](ManifestJson& m) {
    ManifestJson& s = m["simulate"];
    if (!resumed) s = ManifestJson::object();
    s["status"] = "running";
    s["scene"] = ManifestJson::parse(sceneToJson(scene).dump());
    s["solver"] = methodEntry(pressureSolverRegistry(), scene.solver.method).name;
    s["particle_count"] = sim.particleCount();
    if (scene.changesParticleCount()) s["max_particles"] = sim.capacity();
    s["boundary_samples"] = sim.boundaryCount();
    s["gl_renderer"] = result.renderer;
    s["frames"] = ManifestJson::array({write.first, write.last});
    trimFrames(s, resumed.value_or(scene.time.startFrame - 1));
  });

  CacheWriter writer(o.queueCapacity, [&](const FrameOutput& f) {
    removeOtherRestartFiles(o.shotDir, f.restart.frame);
    updateManifest(o.shotDir, [&](ManifestJson& m) {
      ManifestJson entry = frameJson(f.stats);
      entry["written"] = f.cache.has_value();
      m["simulate"]["per_frame"].push_back(entry);
      summarise(m["simulate"]);
    });
  });
  auto output = [&](const FrameStats& stats) {
    FrameOutput out;
    out.stats = stats;
    if (scene.changesParticleCount()) out.stats.particles = sim.particleCount();
    if (write.contains(sim.frame())) {
      out.cache = sim.cacheFrame();
      out.cachePath = particleCachePath(o.shotDir, sim.frame());
      ++result.framesWritten;
    }
    out.restart = sim.saveState();
    out.restartPath = restartPath(o.shotDir, sim.frame());
    out.sceneHash = hash;
    writer.push(std::move(out));
  };

  const int last = write.last;
  Progress progress("simulate", last - sim.frame());
  int64_t steps = 0;
  try {
    if (!resumed) output(FrameStats{scene.time.startFrame, 0, 0, 0, 0, 0});  // the initial state
    while (sim.frame() < last) {
      const FrameStats f = sim.advance();
      for (const std::string& w : f.warnings) progress.warn(fmt::format("frame {}: {}", f.frame, w));
      result.frames.push_back(f);
      output(f);
      steps += f.substeps;
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
      if (o.progress)
        progress.update(
            int64_t(result.frames.size()),
            fmt::format("frame {}, {:.0f} substeps/s, {:.3g} particle-steps/s, dt {:.3g}", f.frame,
                        double(steps) / secs, double(steps) * sim.particleCount() / secs, f.dtMean));
    }
    writer.finish();
  } catch (const std::exception& e) {
    // Frames already handed over are still written; the error wins over a later write error.
    try {
      writer.finish();
    } catch (...) {
    }
    updateManifest(o.shotDir, [&](ManifestJson& m) {
      m["simulate"]["status"] = "failed";
      m["simulate"]["error"] = e.what();
    });
    throw;
  }
  if (o.progress) progress.finish();
  result.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  updateManifest(o.shotDir, [&](ManifestJson& m) {
    m["simulate"]["status"] = "complete";
    m["simulate"]["wall_seconds"] = result.wallSeconds;
  });
  return result;
}

}  // namespace sphfx::sim
