#pragma once
// Zhu & Bridson (2005) smooth spheres, rasterized block by block (internal to the surfacing stage).
#include <openvdb/openvdb.h>

#include <array>
#include <vector>

namespace sphfx::surfacing {

/// The instruction set of the block splat: Auto picks AVX2 where the CPU has it. Both give
/// bit-identical grids; the choice exists for the test that checks that.
enum class SplatIsa { Auto, Baseline, Avx2 };

/// Whether this CPU can run `isa`.
bool splatIsaSupported(SplatIsa isa);

/// phi(x) = |x - xbar(x)| - radius, xbar the mean of the particles within `search` of x weighted by
/// k = (1 - d^2 / search^2)^3, sampled on voxels of `voxelSize` wherever some particle is within
/// `search`; elsewhere outside. Voxels with |phi| < halfWidth voxels are active, the others hold
/// +-halfWidth voxels (inactive). Float arithmetic in voxel units relative to each 8^3 block; every
/// block gathers its particles in a fixed order, so the result does not depend on the thread count.
openvdb::FloatGrid::Ptr rasterizeZhuBridsonBlocks(const std::vector<std::array<float, 3>>& positions,
                                                  double voxelSize, double radius, double search,
                                                  double halfWidth, SplatIsa isa = SplatIsa::Auto);

}  // namespace sphfx::surfacing
