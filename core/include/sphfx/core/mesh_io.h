#pragma once
/// @file mesh_io.h
/// @brief Triangle meshes on disk: binary little-endian PLY with per-vertex normals, the contract between
/// the surfacing and render stages (SHOT/mesh/mesh.####.ply).
///
/// Layout: "element vertex N" with float x y z nx ny nz, then "element face M" with
/// "property list uchar int vertex_indices" (always 3 indices).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace sphfx {

struct TriangleMesh {
  std::vector<std::array<float, 3>> positions;
  std::vector<std::array<float, 3>> normals;  ///< one per position (unit length)
  std::vector<std::array<uint32_t, 3>> triangles;
};

/// Writes `mesh` atomically. @throws InputError if normals and positions differ in count or a triangle
/// indexes past the vertices; IoError on write failure.
void writePly(const std::string& path, const TriangleMesh& mesh);

/// Reads a binary little-endian or ASCII PLY with x/y/z (and optionally nx/ny/nz) vertex properties and
/// triangle faces (quads are split). Missing normals are computed (area-weighted).
/// @throws IoError if unreadable; InputError if malformed, naming the file and what was expected.
TriangleMesh readPly(const std::string& path);

/// Sets one area-weighted unit normal per vertex (zero for vertices of degenerate triangles only).
void computeVertexNormals(TriangleMesh& mesh);

/// SHOT/mesh/mesh.####.ply
std::string meshPath(const std::string& shotDir, int frame);
/// SHOT/surface/surface.####.vdb
std::string surfacePath(const std::string& shotDir, int frame);
/// SHOT/render/<source>.####.<ext>
std::string renderPath(const std::string& shotDir, const std::string& source, int frame,
                       const std::string& ext);

}  // namespace sphfx
