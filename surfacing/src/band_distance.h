#pragma once
// Signed distances in a narrow band from a field's zero crossing (internal to the surfacing stage).
#include <openvdb/openvdb.h>

namespace sphfx::surfacing {

/// Signed distances (world units; negative where `field` <= 0, inside) to the zero crossing of `field`,
/// in `field`'s active voxels:
/// - voxels with a face neighbour across the crossing get first-order distances (the crossing along
///   each axis by linear interpolation, d = 1 / sqrt(sum over axes of 1 / d_a^2), as OpenVDB's fast
///   sweeping starts);
/// - the other active voxels get the first-order (Godunov) update of |grad phi| = 1, reached in groups
///   of increasing distance (group marching, Kim 2001) until a group lies wholly beyond `maxVoxels`
///   voxels, then two relaxation passes.
/// Active voxels not reached hold +-FLT_MAX, as do the inactive voxels of the returned grid's leaves; its
/// tiles and background are `field`'s. The caller sets the narrow band's background and trims.
/// Deterministic: every pass reads only the previous pass's values.
openvdb::FloatGrid::Ptr bandDistances(const openvdb::FloatGrid& field, double maxVoxels);

}  // namespace sphfx::surfacing
