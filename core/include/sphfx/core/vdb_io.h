#pragma once
/// @file vdb_io.h
/// @brief Writing OpenVDB files reproducibly: atomic (temporary name, then rename), Blosc-compressed
/// (Zip where OpenVDB lacks Blosc), and byte-identical for identical grids.
///
/// OpenVDB stamps every archive with a random UUID; sphfx replaces it by one derived from the rest of
/// the file, so that reruns and thread counts never change a cache's bytes (determinism tests compare
/// whole files).

#include <openvdb/openvdb.h>

#include <string>

namespace sphfx {

/// Writes `grids` to `path`. @throws IoError if OpenVDB cannot write or the header is not the layout
/// this version expects.
void writeVdbFile(const std::string& path, const openvdb::GridCPtrVec& grids);

}  // namespace sphfx
