#include "commands.h"
#include "sphfx/core/collider_geometry.h"
#include "sphfx/core/error.h"

#include "sphfx/core/data_files.h"

namespace sphfx::cli {

std::shared_ptr<GLContextOptions> addGLOptions(CLI::App* cmd) {
  auto options = std::make_shared<GLContextOptions>();
  auto name = std::make_shared<std::string>("auto");
  cmd->add_option("--gl", *name,
                  "OpenGL backend: auto (EGL device, then EGL surfaceless, then OSMesa), "
                  "egl-device, egl-surfaceless or osmesa")
      ->check(CLI::IsMember(glBackendNames()))
      // The lambda owns `name` too: CLI11 writes into it after this function has returned.
      ->each([options, name](const std::string& v) { options->backend = parseGLBackend(v); });
  cmd->add_flag("--gl-debug", options->debug,
                "Check GL errors after every dispatch and draw, and print KHR_debug messages (slow)");
  return options;
}

std::string resolveShippedFile(std::string path) {
  return resolveInputFile(path);
}

std::shared_ptr<std::vector<std::string>> addSetOption(CLI::App* cmd, const std::string& what) {
  auto sets = std::make_shared<std::vector<std::string>>();
  cmd->add_option("--set", *sets, what + ", e.g. --set fluid.artificial_viscosity=0.04 (repeatable)")
      ->type_name("PATH=VALUE")
      ->take_all()
      ->allow_extra_args(false);
  return sets;
}

Scene loadSceneAndGeometry(const std::string& file, const std::vector<std::string>& sets,
                           std::vector<size_t>* triangles) {
  Scene scene = loadScene(file, sets);
  try {
    const std::vector<size_t> counts = checkColliderGeometry(scene);
    if (triangles) *triangles = counts;
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
  return scene;
}

}  // namespace sphfx::cli
