#include "shot_files.h"

#include <filesystem>

#include "sphfx/core/mesh_io.h"
#include "sphfx/core/particle_cache.h"

namespace fs = std::filesystem;

namespace sphfx::farm {

std::string farmDir(const std::string& shotDir) {
  return (fs::path(shotDir) / "farm").string();
}
std::string logsDir(const std::string& shotDir) {
  return (fs::path(shotDir) / "farm" / "logs").string();
}
std::string jobsPath(const std::string& shotDir) {
  return (fs::path(shotDir) / "farm" / "jobs.json").string();
}
std::string submitPath(const std::string& shotDir) {
  return (fs::path(shotDir) / "farm" / "submit.json").string();
}
std::string farmScenePath(const std::string& shotDir) {
  return (fs::path(shotDir) / "farm" / "scene.json").string();
}

bool simulationComplete(const std::string& shotDir, const ManifestJson& sceneJson) {
  const ManifestJson m = readManifest(shotDir);
  if (!m.contains("simulate")) return false;
  const ManifestJson& s = m["simulate"];
  return s.value("status", "") == "complete" && s.contains("scene") && s["scene"] == sceneJson;
}

bool holdsOtherSimulation(const std::string& shotDir, const ManifestJson& sceneJson) {
  const ManifestJson m = readManifest(shotDir);
  return m.contains("simulate") && m["simulate"].contains("scene") && m["simulate"]["scene"] != sceneJson;
}

namespace {

std::string sourceName(const Scene& scene) {
  return scene.render.source == RenderSource::Surface ? "surface" : "particles";
}

bool frameDone(const std::string& shotDir, const Scene& scene, const std::string& stage, int frame) {
  std::error_code ec;
  if (stage == "simulate") return fs::exists(particleCachePath(shotDir, frame), ec);
  if (stage == "surface")
    return fs::exists(meshPath(shotDir, frame), ec) && fs::exists(surfacePath(shotDir, frame), ec);
  const std::string ext = scene.render.format == ImageFormat::Exr ? "exr" : "png";
  return fs::exists(renderPath(shotDir, sourceName(scene), frame, ext), ec);
}

}  // namespace

int framesDone(const std::string& shotDir, const Scene& scene, const std::string& stage,
               const FrameRange& range) {
  int done = 0;
  for (int f = range.first; f <= range.last; ++f) done += frameDone(shotDir, scene, stage, f) ? 1 : 0;
  return done;
}

std::string contactSheetPath(const std::string& shotDir, const Scene& scene) {
  return (fs::path(shotDir) / "render" / (sourceName(scene) + "_contact.png")).string();
}

std::string shellQuote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace sphfx::farm
