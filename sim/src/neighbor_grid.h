#pragma once
/// @file neighbor_grid.h
/// @brief Uniform-grid neighbour search on the GPU (cell size = kernel radius h): a counting sort of
/// items by cell. Cell of each item with atomic counts, an exclusive parallel scan of the counts into
/// cell starts, scatter, then a per-cell sort by source index (a stable counting sort, hence a
/// deterministic order) that gathers the items into cell-ordered arrays. Solver passes then visit the
/// 3x3 rows of cells around a particle as 9 contiguous ranges. With splitX > 1 each cell is also ordered
/// by slabs of h / splitX in x, and rowStart() indexes the slabs, so that a walk can cut a row to the
/// x-interval the kernel sphere reaches (sph_kernels.glsl, sphRow()).

#include <array>
#include <cstdint>

#include "dispatch_gate.h"
#include "parallel_scan.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gpu_buffer.h"
#include "sphfx/gpu/shader_program.h"

namespace sphfx::sim {

struct GridSpec {
  std::array<float, 3> min{};
  float cellSize = 1;
  std::array<int, 3> dims{1, 1, 1};
  int splitX = 1;  ///< slabs per cell in x: 1, 2 or 4 (gridSplitX())
  /// Cells in the grid. Index cells() is the extra cell of items out of reach (never visited).
  uint32_t cells() const { return uint32_t(dims[0]) * uint32_t(dims[1]) * uint32_t(dims[2]); }
  /// The scene's domain with cells of the kernel radius, split in x by gridSplitX().
  static GridSpec forScene(const Scene& scene);
};

class NeighborGrid {
 public:
  /// Buffers and programs for `items` items. Registers its dispatches with `gate`. With `liveCount`
  /// (the fluid of a scene whose particle count changes) `items` is the capacity: the build sorts the
  /// first dynLive items (sph_dynamic.glsl, bound at SPHFX_SSBO_SIM_DYNAMIC by the caller) and sets
  /// dynLive to those sorted into the grid's cells; items at SIM_REMOVED_POSITION drop out.
  /// @throws InputError for 2^30 items or more (the sort keys' limit).
  /// @throws GLError if a program does not build.
  NeighborGrid(DispatchGate& gate, const GridSpec& spec, uint32_t items, bool liveCount = false);

  /// Sorts the items (vec4 srcPos/srcVel, `items` of each) by cell into dstPos/dstVel. GPU work only.
  void build(const GpuBuffer& srcPos, const GpuBuffer& srcVel, const GpuBuffer& dstPos,
             const GpuBuffer& dstVel) const;

  /// cells() + 2 entries: the items of cell c are the sorted slots [start[c], start[c + 1]).
  const GpuBuffer& cellStart() const { return cellStart_; }
  /// The starts the neighbour walks index (sphRow()): cells() * splitX + 2 entries, slab q of cell c at
  /// c * splitX + q, then the out-of-reach cell's start and the item count; cellStart() if splitX is 1.
  const GpuBuffer& rowStart() const { return spec_.splitX > 1 ? rowStart_ : cellStart_; }
  /// Source index of each sorted slot.
  const GpuBuffer& sortedIndex() const { return sorted_; }
  const GridSpec& spec() const { return spec_; }
  uint32_t items() const { return items_; }

 private:
  const DispatchGate* gate_;
  GridSpec spec_;
  uint32_t items_;
  mutable GpuBuffer cellStart_;  // cleared by every build
  GpuBuffer rowStart_, cellRank_, sorted_;
  ExclusiveScan scan_;
  bool liveCount_;
  ShaderProgram cells_, scatter_, sort_, live_;
  uint32_t itemEntry_, cellEntry_, liveEntry_ = 0;
};

}  // namespace sphfx::sim
