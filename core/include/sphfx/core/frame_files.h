#pragma once
/// @file frame_files.h
/// @brief Film-style frame file names (particles.0001.vdb), frame ranges and atomic writes.

#include <functional>
#include <string>
#include <vector>

namespace sphfx {

/// "DIR/STEM.####.EXT": the frame number padded to 4 digits (more digits when needed; a minus sign
/// before the padding for negative frames, as Houdini's $F4 does).
std::string framePath(const std::string& dir, const std::string& stem, int frame, const std::string& ext);

/// Frame numbers of the files "STEM.<digits>.EXT" in `dir`, sorted. Temporary files are ignored.
std::vector<int> listFrames(const std::string& dir, const std::string& stem, const std::string& ext);

struct FrameRange {
  int first = 0;
  int last = 0;
  int count() const { return last - first + 1; }
  bool contains(int f) const { return f >= first && f <= last; }
};

/// Parses "A-B" or "A" (negative frames: "-5--1"). When `within` is given, the range must lie inside it.
/// @throws InputError naming the option text and what was expected.
FrameRange parseFrameRange(const std::string& text, const FrameRange* within = nullptr);

/// Writes `path` through a temporary name in the same directory, then renames it, so that readers and
/// a crash (kill -9) never see a partial file. `write` receives the temporary path. The temporary is
/// removed if `write` throws. Parent directories are created.
/// @throws IoError if the rename fails; rethrows what `write` throws.
void writeFileAtomically(const std::string& path,
                         const std::function<void(const std::string& tmpPath)>& write);

/// Atomically writes text to `path`.
void writeTextAtomically(const std::string& path, const std::string& text);

/// Reads a whole file. @throws IoError.
std::string readTextFile(const std::string& path);

}  // namespace sphfx
