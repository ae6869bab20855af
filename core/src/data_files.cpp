#include "sphfx/core/data_files.h"

#include <cstdlib>
#include <filesystem>

#include "sphfx/core/error.h"

namespace fs = std::filesystem;

namespace sphfx {

std::string executablePath() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw IoError("cannot locate the sphfx executable (/proc/self/exe): " + ec.message());
  return self.string();
}

std::string dataDirectory() {
  if (const char* env = std::getenv("SPHFX_DATA_DIR"); env && *env) {
    if (!fs::is_directory(env)) throw IoError(std::string("SPHFX_DATA_DIR: no such folder: ") + env);
    return env;
  }
  const fs::path dir =
      (fs::path(executablePath()).parent_path() / ".." / "share" / "sphfx").lexically_normal();
  if (!fs::is_directory(dir))
    throw IoError("cannot find sphfx's data folder " + dir.string() +
                  " (install with cmake --install, or set SPHFX_DATA_DIR)");
  return dir.string();
}

std::string resolveInputFile(const std::string& path) {
  const fs::path given(path);
  if (path.empty() || given.is_absolute() || fs::exists(given)) return path;
  try {
    const fs::path shipped = fs::path(dataDirectory()) / given;
    if (fs::exists(shipped)) return shipped.string();
  } catch (const IoError&) {
    // No data folder: the caller reports the file the user named.
  }
  return path;
}

}  // namespace sphfx
