#pragma once
// Face neighbours of a leaf's voxels (internal to the surfacing stage).
#include <openvdb/openvdb.h>

#include <optional>

namespace sphfx::surfacing {

/// Reads the six face neighbours of the voxels of one leaf from the leaf's own buffer or from the
/// buffers of the six leaves next to it, looked up once per leaf instead of through an accessor per
/// voxel. A missing neighbour leaf reads as `missing` if given, else as the tree's value there (a tile
/// or the background: one value for all of it).
template <class TreeT>
class FaceNeighbours {
 public:
  using LeafT = typename TreeT::LeafNodeType;
  using ValueT = typename TreeT::ValueType;

  FaceNeighbours(const TreeT& tree, const LeafT& leaf, std::optional<ValueT> missing = std::nullopt)
      : values_(leaf.buffer().data()) {
    for (int a = 0; a < 3; ++a)
      for (int side = 0; side < 2; ++side) {
        openvdb::Coord o = leaf.origin();
        o[a] += side ? int(LeafT::DIM) : -int(LeafT::DIM);
        const LeafT* next = tree.probeConstLeaf(o);
        next_[a][side] = next ? next->buffer().data() : nullptr;
        tile_[a][side] = next ? ValueT() : missing ? *missing : tree.getValue(o);
      }
  }

  /// The value next to voxel `n` (LeafNode offset) along `axis` (0 = x), on the low (side 0) or high
  /// (side 1) side.
  ValueT operator()(openvdb::Index n, int axis, int side) const {
    const int shift = 6 - 3 * axis, local = int(n >> shift) & 7, stride = 1 << shift;
    if (side ? local < 7 : local > 0) return values_[side ? n + stride : n - stride];
    const openvdb::Index wrapped = side ? n - 7 * stride : n + 7 * stride;
    return next_[axis][side] ? next_[axis][side][wrapped] : tile_[axis][side];
  }

 private:
  const ValueT* values_;
  const ValueT* next_[3][2];
  ValueT tile_[3][2];
};

}  // namespace sphfx::surfacing
