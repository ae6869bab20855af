#pragma once
// Zhu & Bridson (2005) smooth spheres, rasterized block by block (internal to the surfacing stage).
#include <openvdb/openvdb.h>

#include <array>
#include <vector>

#include "simd.h"

namespace sphfx::surfacing {

/// phi(x) = |x - xbar(x)| - radius, xbar the mean of the particles within `search` of x weighted by
/// k = (1 - d^2 / search^2)^3, sampled on voxels of `voxelSize` wherever some particle is within
/// `search`; elsewhere outside. Voxels with |phi| < halfWidth voxels are active, the others hold
/// +-halfWidth voxels (inactive). Float arithmetic in voxel units relative to each 8^3 block; every
/// block gathers its particles in a fixed order, so the result does not depend on the thread count.
openvdb::FloatGrid::Ptr rasterizeZhuBridsonBlocks(const std::vector<std::array<float, 3>>& positions,
                                                  double voxelSize, double radius, double search,
                                                  double halfWidth, SimdIsa isa = SimdIsa::Auto);

}  // namespace sphfx::surfacing
