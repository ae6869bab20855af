#pragma once
/// @file collider_geometry.h
/// @brief Colliders given as files: triangle meshes (OBJ, PLY, STL) and OpenVDB level sets, placed at
/// rest (scale, rotation, translation) and turned into a dense signed distance field, negative inside,
/// from which the simulation derives its boundary samples and its no-penetration projection. The field
/// is built with OpenVDB (tools::meshToSignedDistanceField, or meshToUnsignedDistanceField for the
/// shell of a mesh that is not closed) and can be cached as a .vdb file next to the shot.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sphfx/core/mesh_io.h"
#include "sphfx/core/scene.h"

namespace sphfx {

/// Reads the triangles of a mesh file by its extension: .obj (v/f, polygons fanned, negative indices),
/// .ply (readPly) or .stl (ASCII or binary). Vertex normals are computed, not read.
/// @throws IoError if the file cannot be read; InputError "FILE:LINE: what was expected" (binary STL:
/// the triangle number; PLY: the vertex number) for a malformed file, a NaN or infinite coordinate, a
/// face index out of range, an unknown extension, or a file without triangles.
TriangleMesh readColliderMesh(const std::string& path);

/// Edges that only one triangle uses, after welding vertices at identical positions: 0 for a closed
/// (watertight) surface.
size_t countOpenEdges(const TriangleMesh& mesh);

/// The collider's surface at rest as triangles, in the scene's frame: a mesh file placed by scale,
/// rotation and translation; a vdb level set's zero isosurface (tools::volumeToMesh) placed the same way.
/// @throws InputError, IoError as readColliderMesh; InputError naming the file and grid for a vdb file
/// without the grid, with a grid that is not a float level set, or with an empty one.
/// Box and sphere colliders are analytic: InputError.
TriangleMesh colliderRestMesh(const Collider& collider);

/// Reads every mesh and vdb collider's geometry as the simulation will (without building fields):
/// `sphfx scene` runs this so that bad geometry is refused before a shot starts. Returns the triangle
/// count of each collider (0 for analytic ones).
/// @throws InputError "/colliders/INDEX: ..." as colliderRestMesh, and for a mesh that is not closed
/// without a thickness.
std::vector<size_t> checkColliderGeometry(const Scene& scene);

/// Resolution of a collider's field, in metres.
struct FieldSpec {
  double voxel = 0;          ///< voxel size
  double interiorDepth = 0;  ///< depth inside the surface where distances are exact
  double exteriorBand = 0;   ///< distance outside the surface where distances are exact
};

/// The resolution of a scene's collider fields: voxels of half a spacing (two voxels across a wall one
/// spacing thick), exact distances one kernel radius plus a spacing deep (the simulation's boundary
/// samples reach ceil(h / s) spacings in) and one spacing outside (the no-penetration projection).
FieldSpec colliderFieldSpec(const Scene& scene);

/// The path a shot caches collider `index`'s field at: SHOT/colliders/collider.INDEX.vdb.
std::string colliderFieldPath(const std::string& shotDir, size_t index);

/// A signed distance field on a dense voxel block, in the scene's frame at rest: distance[i] at
/// origin + voxel * (i, j, k), x fastest. Beyond the narrow bands it holds +-(band) (OpenVDB's
/// background), with the sign of the side.
struct ColliderField {
  std::array<double, 3> origin{};
  double voxel = 0;
  std::array<int, 3> dims{};
  std::vector<float> distance;
  std::array<double, 3> solidMin{}, solidMax{};  ///< bounds of the solid at rest

  /// Trilinear distance at a rest-frame point; outside the block, the distance to the block plus the
  /// value at its nearest face point (positive: the block spans the whole solid).
  double sample(const Vec3d& p) const;
  size_t voxelCount() const { return distance.size(); }
};

/// The largest dense field sphfx builds per collider (voxels): 4 bytes each on the GPU.
constexpr size_t kMaxColliderFieldVoxels = size_t(64) << 20;

/// Builds collider `index`'s field. With a non-empty `cacheFile`, a field cached there by an earlier run
/// for the same input bytes, placement and spec is read instead of rebuilt (the file carries a key of
/// both), and a rebuilt one is written there atomically. `rebuilt` (optional) tells which happened.
/// @throws InputError naming /colliders/INDEX and the file: unreadable or malformed geometry (as
/// colliderRestMesh), a mesh that is not closed without a thickness (with its open-edge count), a
/// field larger than kMaxColliderFieldVoxels; IoError if the cache cannot be written.
ColliderField buildColliderField(const Collider& collider, size_t index, const FieldSpec& spec,
                                 const std::string& cacheFile = "", bool* rebuilt = nullptr);

}  // namespace sphfx
