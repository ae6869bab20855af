#pragma once
/// @file render_shot.h
/// @brief The render stage of a shot: frames from SHOT/cache (particles) or SHOT/mesh (surface) to
/// SHOT/render/<source>.####.png|exr, a contact sheet, an optional movie, and the manifest's "render"
/// section. This is what `sphfx render` (and `sphfx run`) call.

#include <optional>
#include <string>
#include <vector>

#include "sphfx/core/frame_files.h"
#include "sphfx/core/scene.h"

namespace sphfx::render {

/// Command-line overrides of the scene's render settings (absent: the scene's value).
struct RenderShotOptions {
  std::string shotDir;
  std::optional<FrameRange> frames;  ///< absent: every frame with an input, within the scene's range
  std::optional<RenderSource> source;
  std::optional<int> width, height, samples;
  std::optional<ImageFormat> format;
  bool force = false;        ///< re-render frames that are already newer than their inputs
  bool movie = false;        ///< assemble an MP4 with ffmpeg when it is on PATH (else a warning)
  int contactEvery = 0;      ///< contact sheet of every Nth frame; 0 picks N for about 12 thumbnails
  bool contactSheet = true;  ///< false: frames only (a farm task of a chunk; the last job writes the sheet)
};

struct RenderShotResult {
  int rendered = 0;
  int skipped = 0;
  double seconds = 0;        ///< total wall time of the frames rendered
  std::string renderer;      ///< GL_RENDERER of the context used
  std::string contactSheet;  ///< path of the contact sheet written
  std::string movie;         ///< path of the movie written, empty when none
};

/// The scene of a shot: `sceneFile` when given, otherwise the resolved scene that the simulation stage
/// stored in the manifest ("simulate.scene"). @throws InputError if the shot directory does not exist,
/// or neither source gives a valid scene (the message says to pass --scene).
Scene loadShotScene(const std::string& shotDir, const std::string& sceneFile = {});

/// Parses "WIDTHxHEIGHT" (e.g. "1920x1080"). @throws InputError naming the text and what was expected.
std::pair<int, int> parseImageSize(const std::string& text);

/// Renders the frames of a shot. Needs a current GL context (sphfx::GLContext::create), which the caller
/// owns so that one process can run several stages in one context. Frames whose image exists and is newer
/// than its input are skipped unless `force`. Updates the manifest's "render" section after every frame.
/// @throws InputError for a missing shot, missing inputs or bad options; IoError on unreadable inputs or
/// unwritable outputs; GLError if the GL cannot render.
RenderShotResult renderShot(const Scene& scene, const RenderShotOptions& options);

}  // namespace sphfx::render
