#pragma once
/// @file simulation.h
/// @brief The simulation stage of a shot: a Simulator driven frame by frame, caches written by a writer
/// thread behind a bounded queue (the GPU does not wait on disk), restart files for --resume, the
/// manifest's "simulate" section and a progress line.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sphfx/core/frame_files.h"
#include "sphfx/core/scene.h"

namespace sphfx::sim {

/// What one simulated frame took.
struct FrameStats {
  int frame = 0;
  int substeps = 0;
  double dtMin = 0, dtMean = 0, dtMax = 0;
  double wallSeconds = 0;
  int64_t particles = -1;  ///< particles at the frame's end; -1: the scene's count never changes
  std::vector<std::pair<std::string, double>> solverStats;  ///< the pressure solver's, name and value
  /// What the solver could not trust in this frame (e.g. a DFSPH solve stopped above its tolerance):
  /// logged as warnings and kept in the manifest's per-frame entry.
  std::vector<std::string> warnings;
};

struct SimulationOptions {
  std::string shotDir;
  /// Frames to write (within the scene's); absent: all. Earlier frames are simulated, not written.
  std::optional<FrameRange> frames;
  /// Continue from the latest restart file of the shot (a fresh start if there is none).
  bool resume = false;
  bool progress = true;
  /// Frames the writer queue may hold before the simulation waits.
  size_t queueCapacity = 3;
};

struct SimulationResult {
  std::vector<FrameStats> frames;  ///< frames simulated by this run
  int framesWritten = 0;
  int resumedFrom = 0;  ///< frame the run continued from (0: fresh start)
  uint32_t particles = 0;
  double wallSeconds = 0;
  std::string renderer;
};

/// Simulates `scene` into options.shotDir (SHOT/cache/particles.####.vdb, SHOT/manifest.json), in the
/// current GL context. On a health-check failure the frames finished so far stay on disk (and in the
/// manifest, with status "failed") and SimulationError is rethrown.
/// @throws InputError (frames outside the scene, changed scene on resume), GLError, IoError,
/// SimulationError.
SimulationResult simulateShot(const Scene& scene, const SimulationOptions& options);

}  // namespace sphfx::sim
