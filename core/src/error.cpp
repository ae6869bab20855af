#include "sphfx/core/error.h"

namespace sphfx {

int exitCodeFor(const std::exception& e) noexcept {
  if (dynamic_cast<const InputError*>(&e)) return 2;
  if (dynamic_cast<const SimulationError*>(&e)) return 3;
  return 1;
}

}  // namespace sphfx
