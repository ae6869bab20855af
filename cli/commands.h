#pragma once
// Subcommands of the sphfx executable. Each lives in its own cmd_*.cpp and only parses options and
// calls a stage library.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "sphfx/core/scene.h"
#include "sphfx/gpu/gl_context.h"

namespace sphfx::cli {

/// Adds --gl and --gl-debug to `cmd`; the returned options are filled when the command line is parsed.
std::shared_ptr<GLContextOptions> addGLOptions(CLI::App* cmd);
/// Option transform for input files (scenes, studies, suites): a relative path that does not exist here
/// is looked up in the shipped data folder (sphfx::resolveInputFile).
std::string resolveShippedFile(std::string path);
/// Adds repeatable --set path=value to `cmd`, its help text starting with `what`.
std::shared_ptr<std::vector<std::string>> addSetOption(
    CLI::App* cmd, const std::string& what = "Override a scene parameter");
/// loadScene, then the colliders' geometry files read and checked (checkColliderGeometry), errors
/// prefixed with the scene file: bad geometry fails before a shot starts. Returns the triangle counts.
Scene loadSceneAndGeometry(const std::string& file, const std::vector<std::string>& sets,
                           std::vector<size_t>* triangles = nullptr);

void addInfoCommand(CLI::App& app);
void addSceneCommand(CLI::App& app);
void addStudyCommand(CLI::App& app);
void addStabilityCommand(CLI::App& app);
void addSurfaceCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addSimulateCommand(CLI::App& app);
void addRunCommand(CLI::App& app);
void addInspectCommand(CLI::App& app);
void addFarmCommand(CLI::App& app);

}  // namespace sphfx::cli
