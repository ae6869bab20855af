#include <fmt/format.h>

#include <cstdio>

#include "commands.h"
#include "sphfx/core/error.h"
#include "sphfx/core/log.h"
#include "sphfx/render/render_shot.h"

namespace sphfx::cli {

namespace {

struct RenderArgs {
  std::string shot, frames, source, size, format, scene;
  int samples = 0;
  int contactEvery = 0;
  bool movie = false, force = false, noContactSheet = false;
};

render::RenderShotOptions toOptions(const RenderArgs& a) {
  render::RenderShotOptions o;
  o.shotDir = a.shot;
  if (!a.frames.empty()) o.frames = parseFrameRange(a.frames);
  if (!a.source.empty()) o.source = a.source == "surface" ? RenderSource::Surface : RenderSource::Particles;
  if (!a.size.empty()) {
    const auto [w, h] = render::parseImageSize(a.size);
    o.width = w, o.height = h;
  }
  if (a.samples != 0) o.samples = a.samples;
  if (!a.format.empty()) o.format = a.format == "exr" ? ImageFormat::Exr : ImageFormat::Png;
  o.movie = a.movie;
  o.force = a.force;
  o.contactSheet = !a.noContactSheet;
  if (a.contactEvery < 0) throw InputError("--contact-every: expected a positive frame step");
  o.contactEvery = a.contactEvery;
  return o;
}

}  // namespace

void addRenderCommand(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("render", "Render a shot's frames (SHOT/render/<source>.####.png|exr)");
  auto args = std::make_shared<RenderArgs>();
  cmd->add_option("SHOT", args->shot, "Shot directory")->required();
  cmd->add_option("--frames", args->frames, "Frame range A-B (default: every frame with an input)");
  cmd->add_option("--source", args->source, "surface (meshes) or particles (cache); default: the scene's")
      ->check(CLI::IsMember({"surface", "particles"}));
  cmd->add_option("--size", args->size, "Image size WIDTHxHEIGHT, e.g. 1920x1080; default: the scene's");
  cmd->add_option("--samples", args->samples, "MSAA samples per pixel (1-16, clamped to the GL's maximum)")
      ->check(CLI::Range(1, 16));
  cmd->add_option("--format", args->format, "png (8-bit sRGB) or exr (half RGBA + float Z)")
      ->check(CLI::IsMember({"png", "exr"}));
  cmd->add_option("--scene", args->scene,
                  "Scene file (default: the one the simulation recorded in the manifest)");
  cmd->add_option("--contact-every", args->contactEvery,
                  "Contact sheet of every Nth frame (default: ~12 frames)");
  cmd->add_flag("--no-contact-sheet", args->noContactSheet,
                "Frames only, no contact sheet (a farm chunk; the shot's last job writes the sheet)");
  cmd->add_flag("--movie", args->movie, "Also assemble an MP4 (H.264) with ffmpeg, if installed");
  cmd->add_flag("--force", args->force, "Re-render frames that are already up to date");
  auto gl = addGLOptions(cmd);
  cmd->callback([args, gl] {
    // Validate everything that needs no GL first, so bad input fails fast with exit code 2.
    const render::RenderShotOptions options = toOptions(*args);
    const Scene scene = render::loadShotScene(args->shot, args->scene);
    auto ctx = GLContext::create(*gl);
    const render::RenderShotResult r = render::renderShot(scene, options);
    logInfo(fmt::format("render: {} frames rendered ({}), {} up to date; renderer {}", r.rendered,
                        formatDuration(r.seconds), r.skipped, r.renderer));
    if (!r.contactSheet.empty()) logInfo("contact sheet: " + r.contactSheet);
    if (!r.movie.empty()) logInfo("movie: " + r.movie);
  });
}

}  // namespace sphfx::cli
