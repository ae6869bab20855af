#include "sphfx/core/manifest.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"

namespace fs = std::filesystem;

namespace sphfx {

std::string manifestPath(const std::string& shotDir) {
  return (fs::path(shotDir) / "manifest.json").string();
}

ManifestJson readManifest(const std::string& shotDir) {
  const std::string path = manifestPath(shotDir);
  std::error_code ec;
  if (!fs::exists(path, ec)) return ManifestJson{{"manifest_version", kManifestVersion}};
  try {
    return ManifestJson::parse(readTextFile(path));
  } catch (const ManifestJson::parse_error& e) {
    throw InputError(path + ": invalid JSON: " + e.what());
  }
}

void updateManifest(const std::string& shotDir, const std::function<void(ManifestJson&)>& edit) {
  std::error_code ec;
  fs::create_directories(shotDir, ec);
  const std::string lockPath = (fs::path(shotDir) / ".manifest.lock").string();
  const int fd = ::open(lockPath.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (fd < 0) throw IoError(lockPath + ": cannot open the manifest lock");
  // flock() locks are per open file description, so the lock excludes other processes and other
  // threads of this one alike (each call opens the lock file anew). On NFS Linux maps them to byte-range
  // locks, which the server arbitrates between nodes.
  while (::flock(fd, LOCK_EX) != 0) {
    if (errno == EINTR) continue;
    const int error = errno;
    ::close(fd);
    throw IoError(lockPath + ": cannot lock the manifest: " + std::strerror(error));
  }
  try {
    ManifestJson m = readManifest(shotDir);
    edit(m);
    writeTextAtomically(manifestPath(shotDir), m.dump(2) + "\n");
  } catch (...) {
    ::flock(fd, LOCK_UN);
    ::close(fd);
    throw;
  }
  ::flock(fd, LOCK_UN);
  ::close(fd);
}

}  // namespace sphfx
