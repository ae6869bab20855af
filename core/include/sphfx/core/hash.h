#pragma once
/// @file hash.h
/// @brief FNV-1a 64, the one content hash of sphfx: restart files' scene hash, committed reports' inputs
/// digests, collider field cache keys. Stable across builds and platforms (unlike std::hash).

#include <cstdint>
#include <string>
#include <string_view>

namespace sphfx {

constexpr uint64_t kFnv1aOffset = 1469598103934665603ull;

/// FNV-1a 64 of `bytes`, continuing from `h` (chain calls to hash several pieces).
constexpr uint64_t fnv1a64(std::string_view bytes, uint64_t h = kFnv1aOffset) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

/// fnv1a64 as 16 lower-case hex digits.
std::string fnv1aHex(std::string_view bytes);

}  // namespace sphfx
