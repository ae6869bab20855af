#include <fmt/format.h>

#include "commands.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/log.h"
#include "sphfx/core/scene.h"
#include "sphfx/sim/simulation.h"

namespace sphfx::cli {

void addSimulateCommand(CLI::App& app) {
  CLI::App* cmd =
      app.add_subcommand("simulate", "Simulate a scene on the GPU into per-frame particle caches");
  auto file = std::make_shared<std::string>();
  auto shot = std::make_shared<std::string>();
  auto frames = std::make_shared<std::string>();
  auto resume = std::make_shared<bool>(false);
  cmd->add_option("SCENE", *file, "Scene JSON file")->required()->transform(resolveShippedFile, "", "");
  cmd->add_option("-o,--output", *shot, "Shot directory (caches go to SHOT/cache)")->required();
  cmd->add_option("--frames", *frames, "Frames to write, A-B or A (default: the scene's)");
  cmd->add_flag("--resume", *resume, "Continue from the shot's last complete frame");
  auto sets = addSetOption(cmd);
  auto gl = addGLOptions(cmd);
  cmd->callback([=] {
    const Scene scene = loadSceneAndGeometry(*file, *sets);
    sim::SimulationOptions options;
    options.shotDir = *shot;
    options.resume = *resume;
    if (!frames->empty()) options.frames = parseFrameRange(*frames);
    auto context = GLContext::create(*gl);
    logInfo(fmt::format("{}: {} particles, GL renderer {}", *file, countInitialParticles(scene),
                        context->info().renderer));
    const sim::SimulationResult r = sim::simulateShot(scene, options);
    logInfo(fmt::format("{} frames written to {}/cache in {}", r.framesWritten, *shot,
                        formatDuration(r.wallSeconds)));
  });
}

}  // namespace sphfx::cli
