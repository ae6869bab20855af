// `sphfx run`: simulate -> surface -> render in one process and one GL context. Each stage skips the
// work that is already done (complete simulation of the same scene, surfaces and images newer than their
// inputs), so a re-run is cheap; --from restarts the later stages.
#include <fmt/format.h>

#include <chrono>
#include <filesystem>

#include "commands.h"
#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/log.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/scene.h"
#include "sphfx/render/render_shot.h"
#include "sphfx/sim/simulation.h"
#include "sphfx/surfacing/surfacing.h"

namespace fs = std::filesystem;

namespace sphfx::cli {
namespace {

enum class Stage { Simulate = 0, Surface = 1, Render = 2 };

struct RunOptions {
  std::string sceneFile, shot, frames, from, size, source;
  std::vector<std::string> sets;
  int samples = 0;
  bool movie = false;
};

Stage parseStage(const std::string& name) {
  if (name == "simulate") return Stage::Simulate;
  if (name == "surface") return Stage::Surface;
  if (name == "render") return Stage::Render;
  throw InputError("--from: expected simulate, surface or render, got \"" + name + "\"");
}

/// The simulation of this exact scene already finished in this shot, over all of the scene's frames (a
/// `sphfx simulate --frames` run of part of them is continued, not taken as done).
bool simulationComplete(const std::string& shot, const Scene& scene) {
  const ManifestJson m = readManifest(shot);
  if (!m.contains("simulate")) return false;
  const auto& s = m["simulate"];
  const bool allFrames = s.contains("frames") && s["frames"].is_array() && s["frames"].size() == 2 &&
                         s["frames"][0].get<int>() <= scene.time.startFrame &&
                         s["frames"][1].get<int>() >= scene.time.endFrame;
  return s.value("status", "") == "complete" && allFrames && s.contains("scene") &&
         s["scene"] == ManifestJson::parse(sceneToJson(scene).dump());
}

/// Same scene as the shot's last (interrupted) simulation: continuing it is bit-identical to a fresh run.
bool sameSceneAsShot(const std::string& shot, const Scene& scene) {
  const ManifestJson m = readManifest(shot);
  return m.contains("simulate") && m["simulate"].contains("scene") &&
         m["simulate"]["scene"] == ManifestJson::parse(sceneToJson(scene).dump());
}

void runSimulate(const Scene& scene, const RunOptions& o, bool restart) {
  if (!restart && simulationComplete(o.shot, scene)) {
    logInfo("[1/3] simulate: already complete for this scene, skipped");
    return;
  }
  sim::SimulationOptions options;
  options.shotDir = o.shot;
  options.resume = !restart && sameSceneAsShot(o.shot, scene);
  if (!o.frames.empty()) options.frames = parseFrameRange(o.frames);
  logInfo(fmt::format("[1/3] simulate: {} particles{}", countInitialParticles(scene),
                      options.resume ? ", resuming the shot's last run" : ""));
  const sim::SimulationResult r = sim::simulateShot(scene, options);
  logInfo(fmt::format("[1/3] simulate: {} frames in {}", r.framesWritten, formatDuration(r.wallSeconds)));
}

void runSurface(const RunOptions& o, bool force) {
  surfacing::SurfaceJob job;
  job.shotDir = o.shot;
  job.frames = o.frames;
  job.force = force;
  logInfo("[2/3] surface");
  const surfacing::SurfaceRunReport r = surfacing::surfaceShot(job);
  size_t done = 0;
  for (const auto& f : r.frames) done += f.skipped ? 0 : 1;
  logInfo(fmt::format("[2/3] surface: {} frames surfaced, {} already done", done, r.frames.size() - done));
}

void runRender(const Scene& scene, const RunOptions& o, bool force) {
  render::RenderShotOptions options;
  options.shotDir = o.shot;
  if (!o.frames.empty()) options.frames = parseFrameRange(o.frames);
  if (!o.source.empty())
    options.source = o.source == "particles" ? RenderSource::Particles : RenderSource::Surface;
  if (!o.size.empty()) std::tie(options.width, options.height) = render::parseImageSize(o.size);
  if (o.samples > 0) options.samples = o.samples;
  options.force = force;
  options.movie = o.movie;
  logInfo("[3/3] render");
  const render::RenderShotResult r = render::renderShot(scene, options);
  logInfo(fmt::format("[3/3] render: {} frames rendered, {} already done; contact sheet {}", r.rendered,
                      r.skipped, r.contactSheet));
}

}  // namespace

void addRunCommand(CLI::App& app) {
  CLI::App* cmd =
      app.add_subcommand("run", "Simulate, surface and render a shot end to end (skips work already done)");
  auto o = std::make_shared<RunOptions>();
  cmd->add_option("SCENE", o->sceneFile, "Scene JSON file")
      ->required()
      ->transform(resolveShippedFile, "", "");
  cmd->add_option("-o,--output", o->shot, "Shot directory")->required();
  cmd->add_option("--frames", o->frames, "Frames, A-B or A (default: the scene's)");
  cmd->add_option("--from", o->from,
                  "Restart from this stage: simulate, surface or render (later stages are redone)")
      ->check(CLI::IsMember({"simulate", "surface", "render"}));
  cmd->add_option("--source", o->source, "Render source: surface or particles (default: the scene's)")
      ->check(CLI::IsMember({"surface", "particles"}));
  cmd->add_option("--size", o->size, "Image size WIDTHxHEIGHT (default: the scene's)");
  cmd->add_option("--samples", o->samples, "MSAA samples (default: the scene's)");
  cmd->add_flag("--movie", o->movie, "Also assemble an MP4 if ffmpeg is installed");
  cmd->add_option("--set", o->sets, "Override a scene parameter (repeatable)")->type_name("PATH=VALUE");
  auto gl = addGLOptions(cmd);
  cmd->callback([o, gl] {
    const auto start = std::chrono::steady_clock::now();
    const Scene scene = loadSceneAndGeometry(o->sceneFile, o->sets);
    // Without --from every stage skips what is done; with it, that stage and the later ones are redone
    // and the earlier ones are not run at all.
    const bool restart = !o->from.empty();
    const Stage from = restart ? parseStage(o->from) : Stage::Simulate;
    if (!o->size.empty()) render::parseImageSize(o->size);  // bad input fails before hours of simulation
    auto context = GLContext::create(*gl);
    logInfo(fmt::format("shot {}: GL {} through {}", o->shot, context->info().renderer,
                        toString(context->backend())));
    if (from == Stage::Simulate) runSimulate(scene, *o, restart);
    if (from <= Stage::Surface) runSurface(*o, restart);
    runRender(scene, *o, restart);
    logInfo(fmt::format(
        "shot {} done in {}", o->shot,
        formatDuration(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count())));
  });
}

}  // namespace sphfx::cli
