#include "restart_file.h"

#include <cstring>
#include <filesystem>
#include <fstream>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/hash.h"

namespace sphfx::sim {
namespace {
constexpr char kMagic[8] = {'S', 'P', 'H', 'F', 'X', 'R', 'S', '1'};
std::string cacheDir(const std::string& shotDir) {
  return (std::filesystem::path(shotDir) / "cache").string();
}
}  // namespace

std::string restartPath(const std::string& shotDir, int frame) {
  return framePath(cacheDir(shotDir), ".restart", frame, "bin");
}

uint64_t sceneStateHash(const Scene& scene) {
  schema::Json j = sceneIdentityJson(scene);
  j["time"].erase("end_frame");
  for (const char* k : {"cache", "surface", "render", "name", "limits"}) j.erase(k);
  const std::string text = j.dump();
  return fnv1a64(text);
}

void writeRestartFile(const std::string& path, const SimulatorState& s, uint64_t sceneHash) {
  writeFileAtomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    const int32_t frame = s.frame;
    const uint64_t count = s.position.size();
    out.write(kMagic, 8);
    out.write(reinterpret_cast<const char*>(&frame), 4);
    out.write(reinterpret_cast<const char*>(&sceneHash), 8);
    out.write(reinterpret_cast<const char*>(&count), 8);
    out.write(reinterpret_cast<const char*>(s.position.data()), std::streamsize(count * 16));
    out.write(reinterpret_cast<const char*>(s.velocity.data()), std::streamsize(count * 16));
    out.flush();
    if (!out) throw IoError(path + ": write failed");
  });
}

SimulatorState readRestartFile(const std::string& path, uint64_t sceneHash) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open");
  char magic[8];
  int32_t frame = 0;
  uint64_t hash = 0, count = 0;
  in.read(magic, 8);
  in.read(reinterpret_cast<char*>(&frame), 4);
  in.read(reinterpret_cast<char*>(&hash), 8);
  in.read(reinterpret_cast<char*>(&count), 8);
  if (!in || std::memcmp(magic, kMagic, 8) != 0) throw InputError(path + ": not an sphfx restart file");
  if (hash != sceneHash)
    throw InputError(path +
                     ": the scene changed since this shot was simulated (only time.end_frame, cache, "
                     "surface and render may change for --resume)");
  SimulatorState s;
  s.frame = frame;
  s.position.resize(count);
  s.velocity.resize(count);
  in.read(reinterpret_cast<char*>(s.position.data()), std::streamsize(count * 16));
  in.read(reinterpret_cast<char*>(s.velocity.data()), std::streamsize(count * 16));
  if (!in) throw IoError(path + ": truncated restart file");
  return s;
}

std::optional<int> latestRestartFrame(const std::string& shotDir) {
  const std::vector<int> frames = listFrames(cacheDir(shotDir), ".restart", "bin");
  if (frames.empty()) return std::nullopt;
  return frames.back();
}

void removeOtherRestartFiles(const std::string& shotDir, int keep) {
  for (int f : listFrames(cacheDir(shotDir), ".restart", "bin"))
    if (f != keep) std::filesystem::remove(restartPath(shotDir, f));
}

}  // namespace sphfx::sim
