#pragma once
/// @file data_files.h
/// @brief Where sphfx finds the data it ships (scenes/, studies/, studies/reference/) at run time.
///
/// The data lives beside the executable in the install layout, `<prefix>/bin/sphfx` and
/// `<prefix>/share/sphfx/`; the build tree mirrors that layout (`build/share/sphfx` links to the source
/// folders), so the same lookup serves a build and an installed copy. Nothing is found through a path
/// compiled into the binary.

#include <string>

namespace sphfx {

/// Absolute path of the running executable (from /proc/self/exe).
/// @throws IoError if it cannot be read.
std::string executablePath();

/// The shipped data folder: $SPHFX_DATA_DIR if set, else `<executable's folder>/../share/sphfx`.
/// @throws IoError naming the folder looked for when it does not exist.
std::string dataDirectory();

/// A file the user named on the command line: `path` itself if it exists or is absolute; otherwise the
/// same relative path under dataDirectory() if that exists there (so `sphfx run scenes/dam_break.json`
/// works from any directory with an installed sphfx); otherwise `path` unchanged, so that the error the
/// caller raises names what the user typed.
std::string resolveInputFile(const std::string& path);

}  // namespace sphfx
