#pragma once
// The anisotropic functions with their instruction set chosen (internal: for the tests that compare them).
#include "anisotropic.h"
#include "simd.h"

namespace sphfx::surfacing {

/// computeAnisotropicKernels with the neighbour sums built for `isa` (bit-identical results).
std::vector<AnisotropicKernel> computeAnisotropicKernels(const std::vector<std::array<float, 3>>& positions,
                                                         const AnisotropicSettings& settings, SimdIsa isa);

/// rasterizeAnisotropic with the density splat built for `isa` (bit-identical results).
openvdb::FloatGrid::Ptr rasterizeAnisotropic(const std::vector<AnisotropicKernel>& kernels, double voxelSize,
                                             double halfWidth, const std::function<void(const char*)>& stage,
                                             SimdIsa isa);

}  // namespace sphfx::surfacing
