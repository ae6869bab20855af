#include "sphfx/render/render_shot.h"

#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "renderer.h"
#include "sphfx/core/collider_geometry.h"
#include "sphfx/core/collider_motion.h"
#include "sphfx/core/error.h"
#include "sphfx/core/log.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/mesh_io.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/gpu/gl.h"

extern char** environ;

namespace sphfx::render {

namespace fs = std::filesystem;

Scene loadShotScene(const std::string& shotDir, const std::string& sceneFile) {
  if (!fs::is_directory(shotDir)) throw InputError(fmt::format("{}: shot directory does not exist", shotDir));
  if (!sceneFile.empty()) return loadScene(sceneFile);
  const ManifestJson manifest = readManifest(shotDir);
  if (!manifest.contains("simulate") || !manifest["simulate"].contains("scene"))
    throw InputError(fmt::format("{}: no scene recorded under \"simulate.scene\"; pass --scene FILE",
                                 manifestPath(shotDir)));
  return parseScene(manifest["simulate"]["scene"], manifestPath(shotDir) + " (simulate.scene)");
}

std::pair<int, int> parseImageSize(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 16 ||
      h < 16 || w > 16384 || h > 16384)
    throw InputError(fmt::format("--size: expected WIDTHxHEIGHT with each in [16, 16384], got \"{}\"", text));
  return {w, h};
}

namespace {

struct Settings {
  RenderSource source;
  int width, height, samples;
  ImageFormat format;
  std::string name() const { return source == RenderSource::Surface ? "surface" : "particles"; }
  std::string ext() const { return format == ImageFormat::Exr ? "exr" : "png"; }
};

Settings resolveSettings(const Scene& scene, const RenderShotOptions& o) {
  const RenderSettings& r = scene.render;
  Settings s{o.source.value_or(r.source), o.width.value_or(r.width), o.height.value_or(r.height),
             o.samples.value_or(r.samples), o.format.value_or(r.format)};
  if (s.samples < 1 || s.samples > 16)
    throw InputError(fmt::format("--samples: expected 1..16, got {}", s.samples));
  return s;
}

std::string inputPath(const std::string& shot, const Settings& s, int frame) {
  return s.source == RenderSource::Surface ? meshPath(shot, frame) : particleCachePath(shot, frame);
}

std::vector<int> selectFrames(const Scene& scene, const RenderShotOptions& o, const Settings& s) {
  std::vector<int> frames;
  if (o.frames) {
    for (int f = o.frames->first; f <= o.frames->last; ++f) {
      if (!fs::exists(inputPath(o.shotDir, s, f)))
        throw InputError(fmt::format("{}: missing input for frame {} (run the {} stage first)",
                                     inputPath(o.shotDir, s, f), f,
                                     s.source == RenderSource::Surface ? "surface" : "simulate"));
      frames.push_back(f);
    }
    return frames;
  }
  const bool surface = s.source == RenderSource::Surface;
  const std::string dir = o.shotDir + (surface ? "/mesh" : "/cache");
  for (int f : listFrames(dir, surface ? "mesh" : "particles", surface ? "ply" : "vdb"))
    if (f >= scene.time.startFrame && f <= scene.time.endFrame) frames.push_back(f);
  if (frames.empty())
    throw InputError(fmt::format("{}: no {} inputs for frames {}-{}", dir,
                                 surface ? "mesh" : "particle cache", scene.time.startFrame,
                                 scene.time.endFrame));
  return frames;
}

bool upToDate(const std::string& output, const std::string& input) {
  std::error_code ec;
  const auto out = fs::last_write_time(output, ec);
  if (ec) return false;
  const auto in = fs::last_write_time(input, ec);
  return !ec && out >= in;
}

// The colliders' surfaces at rest, in the scene's frame (mesh and vdb colliders read once per shot).
std::vector<TriangleMesh> colliderMeshes(const Scene& scene) {
  std::vector<TriangleMesh> meshes;
  for (const Collider& c : scene.colliders) {
    if (c.shape == Shape::Box)
      meshes.push_back(makeBox(c.min, c.max));
    else if (c.shape == Shape::Sphere)
      meshes.push_back(makeUvSphere(c.center, c.radius, 32, 64));
    else
      meshes.push_back(withCreaseNormals(colliderRestMesh(c), 40));
  }
  return meshes;
}

// The colliders placed for `time` (colliderPose: translation and rotation about the pivot).
Stage makeStage(const Scene& scene, const std::vector<TriangleMesh>& restMeshes, double time) {
  Stage stage;
  stage.domain = scene.domain;
  for (size_t i = 0; i < scene.colliders.size(); ++i) {
    const ColliderPose pose = colliderPose(scene.colliders[i], time);
    Solid solid;
    solid.mesh = restMeshes[i];
    for (auto& p : solid.mesh.positions) {
      const Vec3d w = pose.toWorld({p[0], p[1], p[2]});
      p = {float(w[0]), float(w[1]), float(w[2])};
    }
    for (auto& n : solid.mesh.normals) {
      const Vec3d w = rotate(pose.rotation, {n[0], n[1], n[2]});
      n = {float(w[0]), float(w[1]), float(w[2])};
    }
    stage.solids.push_back(std::move(solid));
  }
  return stage;
}

Image renderFrame(Renderer& renderer, const Scene& scene, const std::vector<TriangleMesh>& colliders,
                  const Settings& s, const std::string& input, int frame) {
  const double time = scene.frameTime(frame);
  const Stage stage = makeStage(scene, colliders, time);
  const CameraView camera = sceneCamera(scene, time, double(s.width) / s.height);
  if (s.source == RenderSource::Surface) return renderer.renderSurface(readPly(input), stage, camera);
  const ParticleFrame cache = readParticleCache(input);
  std::vector<ParticleInstance> particles(cache.size());
  for (size_t i = 0; i < cache.size(); ++i) {
    const auto& p = cache.position[i];
    const auto& v = cache.velocity[i];
    particles[i] = {{p[0], p[1], p[2]}, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])};
  }
  ParticleStyle style;
  // The cache's own spacing (what was simulated) wins over the scene's, which --scene may have changed.
  style.radius = float((cache.particleSpacing > 0 ? cache.particleSpacing : scene.fluid.spacing) / 2);
  style.colorBy = scene.render.colorBy;
  style.heightMin = float(scene.domain.min[1]);
  style.heightMax = float(scene.domain.max[1]);
  // White at the free-fall speed over the domain height: the fastest a dam break gets.
  const double g = std::sqrt(scene.gravity[0] * scene.gravity[0] + scene.gravity[1] * scene.gravity[1] +
                             scene.gravity[2] * scene.gravity[2]);
  style.speedScale = float(std::max(std::sqrt(2 * g * (scene.domain.max[1] - scene.domain.min[1])), 1e-3));
  return renderer.renderParticles(particles, style, stage, camera);
}

void writeImage(const std::string& path, const Image& image, ImageFormat format) {
  if (format == ImageFormat::Exr)
    writeExr(path, image);
  else
    writePng(path, encodeSrgb8(image));
}

Image8 readThumbnail(const std::string& path, ImageFormat format) {
  const Image8 full = format == ImageFormat::Exr ? encodeSrgb8(readExrRgba(path)) : readPng(path);
  return downscale(full, 320);
}

std::string writeContactSheet(const std::string& shot, const Settings& s, const std::vector<int>& frames,
                              int every) {
  if (every <= 0) every = std::max(1, int(frames.size() + 11) / 12);
  std::vector<Image8> thumbs;
  for (size_t i = 0; i < frames.size(); i += size_t(every)) {
    const std::string path = renderPath(shot, s.name(), frames[i], s.ext());
    if (fs::exists(path)) thumbs.push_back(readThumbnail(path, s.format));
  }
  if (thumbs.empty()) return {};
  const std::string out = shot + "/render/" + s.name() + "_contact.png";
  writePng(out, contactSheet(thumbs, 4));
  return out;
}

std::string findOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::string candidate = dirs.substr(start, end - start) + "/" + program;
    if (end > start && access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return {};
}

/// Runs a program without a shell (no quoting issues with shot paths). Returns its exit status.
int runProgram(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, args[0].c_str(), nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string writeMovie(const std::string& shot, const Settings& s, const Scene& scene,
                       const std::vector<int>& frames) {
  const std::string ffmpeg = findOnPath("ffmpeg");
  if (ffmpeg.empty()) {
    logWarning("--movie: ffmpeg is not on PATH; no movie written (the frames are in " + shot + "/render)");
    return {};
  }
  const std::string out = shot + "/render/" + s.name() + ".mp4";
  std::vector<std::string> args = {ffmpeg,          "-y",
                                   "-loglevel",     "error",
                                   "-framerate",    fmt::format("{}", scene.time.fps),
                                   "-start_number", std::to_string(frames.front())};
  if (s.format == ImageFormat::Exr) args.insert(args.end(), {"-apply_trc", "iec61966_2_1"});  // EXR is linear
  args.insert(args.end(), {"-i", shot + "/render/" + s.name() + ".%04d." + s.ext(), "-frames:v",
                           std::to_string(frames.back() - frames.front() + 1), "-c:v", "libx264", "-pix_fmt",
                           "yuv420p", "-vf", "scale=trunc(iw/2)*2:trunc(ih/2)*2", out});
  const int status = runProgram(args);
  if (status != 0) {
    logWarning(fmt::format("--movie: ffmpeg failed (exit status {}); no movie written", status));
    return {};
  }
  return out;
}

void recordFrame(const std::string& shot, const Settings& s, const std::string& renderer, int samples,
                 int frame, double seconds) {
  updateManifest(shot, [&](ManifestJson& m) {
    ManifestJson& r = m["render"];
    r["source"] = s.name();
    r["format"] = s.ext();
    r["width"] = s.width;
    r["height"] = s.height;
    r["samples"] = samples;
    r["renderer"] = renderer;
    r["frames"][fmt::format("{:04d}", frame)] = {
        {"seconds", seconds},
        {"file", fs::path(renderPath(shot, s.name(), frame, s.ext())).filename().string()}};
  });
}

}  // namespace

RenderShotResult renderShot(const Scene& scene, const RenderShotOptions& options) {
  if (!fs::is_directory(options.shotDir))
    throw InputError(fmt::format("{}: shot directory does not exist", options.shotDir));
  const Settings s = resolveSettings(scene, options);
  const std::vector<int> frames = selectFrames(scene, options, s);
  RenderShotResult result;
  result.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  std::unique_ptr<Renderer> renderer;  // created on the first frame that needs it: re-runs stay cheap
  std::vector<TriangleMesh> colliders;
  Progress progress("render " + s.name(), int64_t(frames.size()));
  for (size_t i = 0; i < frames.size(); ++i) {
    const int frame = frames[i];
    const std::string input = inputPath(options.shotDir, s, frame);
    const std::string output = renderPath(options.shotDir, s.name(), frame, s.ext());
    if (!options.force && upToDate(output, input)) {
      ++result.skipped;
      progress.update(int64_t(i + 1), fmt::format("frame {} up to date", frame));
      continue;
    }
    const auto start = std::chrono::steady_clock::now();
    if (!renderer) {
      renderer = std::make_unique<Renderer>(s.width, s.height, s.samples);
      colliders = colliderMeshes(scene);
    }
    writeImage(output, renderFrame(*renderer, scene, colliders, s, input, frame), s.format);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.seconds += seconds;
    ++result.rendered;
    recordFrame(options.shotDir, s, result.renderer, renderer->samples(), frame, seconds);
    progress.update(int64_t(i + 1), fmt::format("frame {} {:.2f}s", frame, seconds));
  }
  progress.finish(fmt::format("{} rendered, {} up to date", result.rendered, result.skipped));
  if (!options.contactSheet && !options.movie) return result;
  if (options.contactSheet)
    result.contactSheet = writeContactSheet(options.shotDir, s, frames, options.contactEvery);
  if (options.movie) result.movie = writeMovie(options.shotDir, s, scene, frames);
  updateManifest(options.shotDir, [&](ManifestJson& m) {
    if (!result.contactSheet.empty())
      m["render"]["contact_sheet"] = fs::path(result.contactSheet).filename().string();
    if (!result.movie.empty()) m["render"]["movie"] = fs::path(result.movie).filename().string();
  });
  return result;
}

}  // namespace sphfx::render
