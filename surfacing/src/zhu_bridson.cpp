// Zhu & Bridson smooth spheres on 8^3 blocks. Replaces openvdb::points::rasterizeSmoothSpheres, which
// works in double precision on a PointDataGrid and visits the same voxels several times (mask, then
// transfer); this gathers each block's particles once, in floats relative to the block.
#include "zhu_bridson.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <unordered_map>

namespace sphfx::surfacing {
namespace {

uint64_t packKey(int64_t x, int64_t y, int64_t z) {
  constexpr int64_t kBias = int64_t(1) << 20;
  return (uint64_t(x + kBias) << 42) | (uint64_t(y + kBias) << 21) | uint64_t(z + kBias);
}

/// Per-voxel sums of the block: weights and weighted positions, z fastest (LeafNode's order).
struct Accumulator {
  alignas(32) std::array<float, 512> w, x, y, z;
  void clear() {
    w.fill(0.f);
    x.fill(0.f);
    y.fill(0.f);
    z.fill(0.f);
  }
};

// A z row of a block is one Float8 (simd.h). Without FMA contraction (ISO C++ mode keeps
// -ffp-contract=off) the baseline and AVX2 builds of gatherBlock compute the same roundings, so the
// output does not depend on the CPU (tests/surfacing compares the two).

/// Adds the kernel of the particle at `p` (index space, relative to the block's first voxel).
/// Each (x, y) row within reach is evaluated on all 8 of its z voxels at once, without bounds: a
/// voxel beyond reach gets weight 0 and adds exactly 0 (rows are 2-6 voxels long at the default
/// kernel, so per-voxel bounds cost more than they save).
inline __attribute__((always_inline)) void splat(const openvdb::Vec3f& p, float reach, Accumulator& acc) {
  // Most of the 27 blocks that gather a particle lie beyond its reach on some axis.
  for (int a = 0; a < 3; ++a)
    if (p[a] + reach < 0.f || p[a] - reach > 7.f) return;
  const float reach2 = reach * reach, inv2 = 1.f / reach2;
  const Float8 dz = Float8{0, 1, 2, 3, 4, 5, 6, 7} - p[2], dz2 = dz * dz, zero = {};
  const int x0 = std::max(0, int(std::ceil(p[0] - reach))), x1 = std::min(7, int(std::floor(p[0] + reach)));
  for (int x = x0; x <= x1; ++x) {
    const float dx = float(x) - p[0], dx2 = dx * dx;
    const float ry = std::sqrt(std::max(0.f, reach2 - dx2));
    const int y0 = std::max(0, int(std::ceil(p[1] - ry))), y1 = std::min(7, int(std::floor(p[1] + ry)));
    for (int y = y0; y <= y1; ++y) {
      const float dy = float(y) - p[1], dxy2 = dx2 + dy * dy;
      const int n = (x << 6) | (y << 3);
      const Float8 u = 1.f - (dxy2 + dz2) * inv2;
      const Float8 t = u > zero ? u : zero;
      const Float8 k = t * t * t;
      store8(acc.w.data() + n, load8(acc.w.data() + n) + k);
      store8(acc.x.data() + n, load8(acc.x.data() + n) + k * p[0]);
      store8(acc.y.data() + n, load8(acc.y.data() + n) + k * p[1]);
      store8(acc.z.data() + n, load8(acc.z.data() + n) + k * p[2]);
    }
  }
}

/// Particles binned by 8^3 block: each bin's range in the gather order.
using BlockBins = std::unordered_map<uint64_t, std::pair<size_t, size_t>>;

/// Clears `acc` and adds the kernels of every particle binned within `reachBlocks` of block `b`, in a
/// fixed order; false if no particle was gathered.
inline __attribute__((always_inline)) bool gatherBlock(const openvdb::Coord& b, int reachBlocks, float reach,
                                                       const BlockBins& bins,
                                                       const std::vector<openvdb::Vec3d>& sortedVoxels,
                                                       Accumulator& acc) {
  const openvdb::Coord origin = b << 3;
  acc.clear();
  bool touched = false;
  for (int dx = -reachBlocks; dx <= reachBlocks; ++dx)
    for (int dy = -reachBlocks; dy <= reachBlocks; ++dy)
      for (int dz = -reachBlocks; dz <= reachBlocks; ++dz) {
        auto it = bins.find(packKey(b.x() + dx, b.y() + dy, b.z() + dz));
        if (it == bins.end()) continue;
        for (size_t k = it->second.first; k < it->second.second; ++k) {
          const auto& q = sortedVoxels[k];
          const openvdb::Vec3f p(float(q[0] - origin.x()), float(q[1] - origin.y()),
                                 float(q[2] - origin.z()));
          splat(p, reach, acc);
          touched = true;
        }
      }
  return touched;
}

// gatherBlock compiled twice; the caller picks one per rasterization (one call per block).
bool gatherBlockBaseline(const openvdb::Coord& b, int reachBlocks, float reach, const BlockBins& bins,
                         const std::vector<openvdb::Vec3d>& sortedVoxels, Accumulator& acc) {
  return gatherBlock(b, reachBlocks, reach, bins, sortedVoxels, acc);
}

SPHFX_TARGET_AVX2 bool gatherBlockAvx2(const openvdb::Coord& b, int reachBlocks, float reach,
                                       const BlockBins& bins, const std::vector<openvdb::Vec3d>& sortedVoxels,
                                       Accumulator& acc) {
  return gatherBlock(b, reachBlocks, reach, bins, sortedVoxels, acc);
}

}  // namespace

openvdb::FloatGrid::Ptr rasterizeZhuBridsonBlocks(const std::vector<std::array<float, 3>>& positions,
                                                  double voxelSize, double radius, double search,
                                                  double halfWidth, SimdIsa isa) {
  using LeafT = openvdb::FloatTree::LeafNodeType;
  auto grid = openvdb::createLevelSet<openvdb::FloatGrid>(voxelSize, halfWidth);
  if (positions.empty()) return grid;
  const double inv = 1.0 / voxelSize;
  const float background = float(voxelSize * halfWidth);
  auto blockOf = [&](const std::array<float, 3>& p) {
    return openvdb::Coord(int(std::floor(p[0] * inv)), int(std::floor(p[1] * inv)),
                          int(std::floor(p[2] * inv))) >>
           3;
  };
  // Particles sorted by block, then index: a fixed gather order.
  std::vector<std::pair<uint64_t, uint32_t>> keyed(positions.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, positions.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const auto b = blockOf(positions[i]);
      keyed[i] = {packKey(b.x(), b.y(), b.z()), uint32_t(i)};
    }
  });
  tbb::parallel_sort(keyed.begin(), keyed.end());
  BlockBins bins;
  std::vector<openvdb::Coord> occupied;
  for (size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) {
      bins[keyed[i].first] = {i, i};
      occupied.push_back(blockOf(positions[keyed[i].second]));
    }
    bins[keyed[i].first].second = i + 1;
  }
  // Positions in voxel units in gather order: contiguous, and converted once rather than per block.
  std::vector<openvdb::Vec3d> sortedVoxels(keyed.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, keyed.size(), 4096), [&](const auto& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const auto& q = positions[keyed[k].second];
      sortedVoxels[k] = openvdb::Vec3d(q[0] * inv, q[1] * inv, q[2] * inv);
    }
  });
  const float reach = float(search * inv);
  const int reachBlocks = int(std::ceil((reach + 1) / 8.0));
  std::vector<openvdb::Coord> blocks;
  blocks.reserve(occupied.size() * 8);
  for (const auto& b : occupied)
    for (int dx = -reachBlocks; dx <= reachBlocks; ++dx)
      for (int dy = -reachBlocks; dy <= reachBlocks; ++dy)
        for (int dz = -reachBlocks; dz <= reachBlocks; ++dz) blocks.push_back(b.offsetBy(dx, dy, dz));
  tbb::parallel_sort(blocks.begin(), blocks.end());
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());

  std::vector<std::unique_ptr<LeafT>> leaves(blocks.size());
  const float radiusVoxels = float(radius * inv);
  const auto gather = useAvx2(isa) ? gatherBlockAvx2 : gatherBlockBaseline;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks.size(), 4), [&](const auto& r) {
    Accumulator acc;
    for (size_t bi = r.begin(); bi != r.end(); ++bi) {
      const openvdb::Coord b = blocks[bi], origin = b << 3;
      const bool touched = gather(b, reachBlocks, reach, bins, sortedVoxels, acc);
      if (!touched) continue;
      auto leaf = std::make_unique<LeafT>(origin, background, false);
      bool any = false;
      for (openvdb::Index n = 0; n < LeafT::SIZE; ++n) {
        if (acc.w[n] <= 0.f) continue;  // out of every particle's reach: outside
        const auto c = LeafT::offsetToLocalCoord(n);
        const float iw = 1.f / acc.w[n];
        const float ex = float(c.x()) - acc.x[n] * iw, ey = float(c.y()) - acc.y[n] * iw,
                    ez = float(c.z()) - acc.z[n] * iw;
        const float phi = float(voxelSize) * (std::sqrt(ex * ex + ey * ey + ez * ez) - radiusVoxels);
        if (phi >= background) continue;
        any = true;
        if (phi <= -background)
          leaf->setValueOff(n, -background);
        else
          leaf->setValueOn(n, phi);
      }
      if (any) leaves[bi] = std::move(leaf);
    }
  });
  for (auto& leaf : leaves)
    if (leaf) grid->tree().addLeaf(leaf.release());
  return grid;
}

}  // namespace sphfx::surfacing
