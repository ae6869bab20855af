#pragma once
/// @file restart_file.h
/// @brief Restart files, SHOT/cache/.restart.####.bin: the exact simulator state after a frame
/// (float positions with ids, velocities, in buffer order) so that `--resume` continues bit-identically
/// to an uninterrupted run. Binary, little-endian: magic "SPHFXRS1", int32 frame, uint64 scene hash,
/// uint64 count, count x 16 bytes positions (w = id bits), count x 16 bytes velocities. Written
/// atomically; the simulation keeps only the latest.

#include <cstdint>
#include <optional>
#include <string>

#include "simulator.h"
#include "sphfx/core/scene.h"

namespace sphfx::sim {

std::string restartPath(const std::string& shotDir, int frame);

/// Hash of what decides the simulated motion: the resolved scene without time.end_frame, cache,
/// surface and render (a resumed run may extend the shot or change those).
uint64_t sceneStateHash(const Scene& scene);

/// @throws IoError.
void writeRestartFile(const std::string& path, const SimulatorState& state, uint64_t sceneHash);
/// @throws IoError if unreadable or truncated; InputError if it is not a restart file or `sceneHash`
/// differs (the scene changed since the run that wrote it).
SimulatorState readRestartFile(const std::string& path, uint64_t sceneHash);

/// The frame of the latest restart file in the shot, if any.
std::optional<int> latestRestartFrame(const std::string& shotDir);

/// Removes restart files of frames other than `keep`.
void removeOtherRestartFiles(const std::string& shotDir, int keep);

}  // namespace sphfx::sim
