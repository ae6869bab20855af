#include <fmt/format.h>

#include <cstdio>

#include "commands.h"
#include "sphfx/core/collider_geometry.h"
#include "sphfx/core/error.h"
#include "sphfx/core/log.h"
#include "sphfx/core/scene.h"

namespace sphfx::cli {

void addSceneCommand(CLI::App& app) {
  CLI::App* cmd =
      app.add_subcommand("scene", "Validate a scene and print it resolved (every default filled in)");
  auto file = std::make_shared<std::string>();
  auto schemaFlag = std::make_shared<bool>(false);
  cmd->add_option("SCENE", *file, "Scene JSON file")->transform(resolveShippedFile, "", "");
  cmd->add_flag("--schema", *schemaFlag, "Print the parameter reference (Markdown) instead");
  auto sets = addSetOption(cmd);
  cmd->callback([file, schemaFlag, sets] {
    if (*schemaFlag) {
      std::fputs(sceneReferenceMarkdown().c_str(), stdout);
      return;
    }
    if (file->empty()) throw InputError("scene: expected a SCENE file (or --schema)");
    std::vector<size_t> triangles;
    const Scene scene = loadSceneAndGeometry(*file, *sets, &triangles);
    std::printf("%s\n", sceneToJson(scene).dump(2).c_str());
    for (size_t i = 0; i < triangles.size(); ++i)
      if (triangles[i] > 0) logInfo(fmt::format("collider {}: {} triangles", i, triangles[i]));
    logInfo(fmt::format("{}: valid; {} particles, kernel radius {:g} m, particle mass {:g} kg, {} frames",
                        *file, countInitialParticles(scene), scene.kernelRadius(), scene.particleMass(),
                        scene.time.endFrame - scene.time.startFrame + 1));
  });
}

}  // namespace sphfx::cli
