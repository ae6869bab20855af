#include "sphfx/core/frame_files.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "sphfx/core/error.h"

namespace fs = std::filesystem;

namespace sphfx {

std::string framePath(const std::string& dir, const std::string& stem, int frame, const std::string& ext) {
  const std::string number = frame < 0 ? fmt::format("-{:04d}", -frame) : fmt::format("{:04d}", frame);
  return (fs::path(dir) / (stem + "." + number + "." + ext)).string();
}

std::vector<int> listFrames(const std::string& dir, const std::string& stem, const std::string& ext) {
  std::vector<int> frames;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return frames;
  const std::regex pattern(std::regex_replace(stem, std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
                           R"(\.(-?\d+)\.)" + ext);
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::smatch m;
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, m, pattern)) frames.push_back(std::stoi(m[1].str()));
  }
  std::sort(frames.begin(), frames.end());
  return frames;
}

FrameRange parseFrameRange(const std::string& text, const FrameRange* within) {
  static const std::regex pattern(R"(\s*(-?\d+)\s*(?:-\s*(-?\d+)\s*)?)");
  std::smatch m;
  if (!std::regex_match(text, m, pattern))
    throw InputError("--frames " + text + ": expected A-B or A (e.g. 1001-1048)");
  FrameRange r;
  try {
    r.first = std::stoi(m[1].str());
    r.last = m[2].matched ? std::stoi(m[2].str()) : r.first;
  } catch (const std::out_of_range&) {
    throw InputError("--frames " + text + ": frame number out of range");
  }
  if (r.last < r.first) throw InputError("--frames " + text + ": the last frame is before the first");
  if (within && (r.first < within->first || r.last > within->last))
    throw InputError(fmt::format("--frames {}: expected frames within the scene's {}-{}", text, within->first,
                                 within->last));
  return r;
}

void writeFileAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  static std::atomic<unsigned> counter{0};
  const fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) fs::create_directories(target.parent_path(), ec);
  // Hidden, unique per process and call, and in the same directory so that rename() is atomic.
  const fs::path tmp = target.parent_path() / fmt::format(".{}.tmp.{}.{}", target.filename().string(),
                                                          getpid(), counter.fetch_add(1));
  try {
    write(tmp.string());
    // Flush file data before the rename makes the file visible, so a power cut never leaves a named,
    // empty file.
    if (int fd = ::open(tmp.c_str(), O_RDONLY); fd >= 0) {
      ::fsync(fd);
      ::close(fd);
    }
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw IoError(path + ": cannot write: " + ec.message());
  }
}

void writeTextAtomically(const std::string& path, const std::string& text) {
  writeFileAtomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    if (!out) throw IoError(path + ": cannot write");
  });
}

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace sphfx
