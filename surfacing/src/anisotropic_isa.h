#pragma once
// computeAnisotropicKernels with its instruction set chosen (internal: for the test that compares them).
#include "simd.h"
#include "sphfx/surfacing/anisotropic.h"

namespace sphfx::surfacing {

/// computeAnisotropicKernels with the neighbour sums built for `isa` (bit-identical results).
std::vector<AnisotropicKernel> computeAnisotropicKernels(const std::vector<std::array<float, 3>>& positions,
                                                         const AnisotropicSettings& settings, SimdIsa isa);

}  // namespace sphfx::surfacing
