#pragma once
/// @file particle_cache.h
/// @brief The particle cache: one OpenVDB PointDataGrid per frame (grid "points", Blosc-compressed),
/// the contract between the simulation and the surfacing/render stages.
///
/// Format version 1: attributes P (always), v (always), density, pressure (float) and id (int32) when
/// the scene asks. File metadata: "sphfx_cache_version" (int), "frame" (int), "time" (s),
/// "particle_spacing" (m), "particle_count". Readable unchanged by vdb_print and Houdini.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace sphfx {

constexpr int kParticleCacheVersion = 1;

struct ParticleFrame {
  int frame = 0;
  double time = 0;             ///< simulated seconds since the start frame
  double particleSpacing = 0;  ///< the scene's spacing (m); surfacing derives its defaults from it
  std::vector<std::array<float, 3>> position;
  std::vector<std::array<float, 3>> velocity;
  std::vector<float> density;   ///< empty when not stored
  std::vector<float> pressure;  ///< empty when not stored
  std::vector<int32_t> id;      ///< empty when not stored

  size_t size() const { return position.size(); }
};

/// Writes `frame` to `path` atomically (temporary name, then rename).
/// @throws InputError if attribute arrays disagree in length; IoError on write failure.
void writeParticleCache(const std::string& path, const ParticleFrame& frame);

/// What readParticleCache fills in.
enum class CacheFields {
  All,       ///< every stored attribute
  Positions  ///< positions only (velocity, density, pressure and id left empty, and not decompressed)
};

/// Reads a cache file. Points come back in the grid's storage order (voxel by voxel), which is
/// deterministic but not the written order; use `id` to match particles across frames.
/// @throws IoError if unreadable; InputError if it is not an sphfx particle cache of a known version.
ParticleFrame readParticleCache(const std::string& path, CacheFields fields = CacheFields::All);

/// Path of frame `frame` in a shot: SHOT/cache/particles.####.vdb.
std::string particleCachePath(const std::string& shotDir, int frame);

}  // namespace sphfx
