#include "sphfx/core/hash.h"

#include <fmt/format.h>

namespace sphfx {

std::string fnv1aHex(std::string_view bytes) {
  return fmt::format("{:016x}", fnv1a64(bytes));
}

}  // namespace sphfx
