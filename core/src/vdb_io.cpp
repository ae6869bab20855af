#include "sphfx/core/vdb_io.h"

#include <cctype>
#include <cstdio>
#include <fstream>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"

namespace sphfx {
namespace {

// OpenVDB archive header: magic (8 bytes), file version (4), library major and minor (4 + 4), a "has
// grid offsets" byte (1), then the UUID as 36 characters of text.
constexpr size_t kUuidOffset = 21, kUuidSize = 36;

/// UUID-formatted text from two FNV-1a 64-bit hashes (different seeds) of `bytes`.
std::string contentUuid(const std::string& bytes) {
  uint64_t h[2] = {0xcbf29ce484222325ull, 0x84222325cbf29ce4ull};
  for (unsigned char c : bytes)
    for (auto& x : h) x = (x ^ c) * 0x100000001b3ull;
  char hex[33];
  std::snprintf(hex, sizeof hex, "%016llx%016llx", static_cast<unsigned long long>(h[0]),
                static_cast<unsigned long long>(h[1]));
  const std::string s(hex);
  return s.substr(0, 8) + "-" + s.substr(8, 4) + "-" + s.substr(12, 4) + "-" + s.substr(16, 4) + "-" +
         s.substr(20, 12);
}

bool looksLikeUuid(const std::string& s) {
  if (s.size() != kUuidSize) return false;
  for (size_t i = 0; i < s.size(); ++i) {
    const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
    if (dash ? s[i] != '-' : !std::isxdigit(static_cast<unsigned char>(s[i]))) return false;
  }
  return true;
}

void makeUuidDeterministic(const std::string& path, const std::string& target) {
  const std::string bytes = readTextFile(path);
  if (bytes.size() < kUuidOffset + kUuidSize || !looksLikeUuid(bytes.substr(kUuidOffset, kUuidSize)))
    throw IoError(target + ": unexpected OpenVDB header layout (no archive UUID at byte 21)");
  std::string rest = bytes.substr(0, kUuidOffset);
  rest.append(bytes, kUuidOffset + kUuidSize, std::string::npos);
  const std::string uuid = contentUuid(rest);
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(std::streamoff(kUuidOffset));
  f.write(uuid.data(), std::streamsize(uuid.size()));
  if (!f) throw IoError(target + ": cannot rewrite the archive UUID");
}

}  // namespace

void writeVdbFile(const std::string& path, const openvdb::GridCPtrVec& grids) {
  writeFileAtomically(path, [&](const std::string& tmp) {
    openvdb::io::File file(tmp);
    file.setCompression(openvdb::io::Archive::hasBloscCompression()
                            ? openvdb::io::COMPRESS_BLOSC | openvdb::io::COMPRESS_ACTIVE_MASK
                            : openvdb::io::COMPRESS_ZIP | openvdb::io::COMPRESS_ACTIVE_MASK);
    try {
      file.write(grids);
    } catch (const openvdb::Exception& e) {
      throw IoError(path + ": " + e.what());
    }
    file.close();
    makeUuidDeterministic(tmp, path);
  });
}

}  // namespace sphfx
