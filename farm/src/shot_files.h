#pragma once
// What the farm reads from a shot's own files: which frames each stage has finished, where SHOT/farm/
// keeps its records. Internal to sphfx_farm.

#include <string>

#include "sphfx/core/frame_files.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/scene.h"

namespace sphfx::farm {

std::string farmDir(const std::string& shotDir);
std::string logsDir(const std::string& shotDir);
std::string jobsPath(const std::string& shotDir);
std::string submitPath(const std::string& shotDir);
std::string farmScenePath(const std::string& shotDir);

/// The simulation of exactly `sceneJson` (resolved) finished in this shot.
bool simulationComplete(const std::string& shotDir, const ManifestJson& sceneJson);

/// The shot holds (part of) a simulation of a scene other than `sceneJson`.
bool holdsOtherSimulation(const std::string& shotDir, const ManifestJson& sceneJson);

/// The frames of `range` whose outputs of `stage` ("simulate", "surface", "render") exist.
int framesDone(const std::string& shotDir, const Scene& scene, const std::string& stage,
               const FrameRange& range);

/// The contact sheet the finish job writes: SHOT/render/<source>_contact.png.
std::string contactSheetPath(const std::string& shotDir, const Scene& scene);

/// Shell single-quoting: 'it'\''s'.
std::string shellQuote(const std::string& text);

}  // namespace sphfx::farm
