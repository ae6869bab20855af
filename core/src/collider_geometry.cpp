#include "sphfx/core/collider_geometry.h"

#include <fmt/format.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "sphfx/core/collider_motion.h"
#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/hash.h"
#include "sphfx/core/vdb_io.h"

namespace sphfx {
namespace {

using P3 = std::array<float, 3>;

// Three coordinates from a stream of tokens, as strtof reads them ("nan" and "inf" included, so that
// they are reported as such rather than as a syntax error).
bool readPoint(std::istream& in, P3& p) {
  for (float& c : p) {
    std::string tok;
    if (!(in >> tok)) return false;
    char* end = nullptr;
    c = std::strtof(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0') return false;
  }
  return true;
}

bool finite(const P3& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

std::string lowerExtension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

// OBJ: "v x y z [w]" and "f a b c ..." (a = i, i/t, i//n or i/t/n; negative: relative to the end).
// Everything else (vt, vn, g, o, s, usemtl, mtllib, comments) carries nothing a collider needs.
TriangleMesh readObj(const std::string& path) {
  std::istringstream in(readTextFile(path));
  TriangleMesh m;
  std::string line;
  for (size_t lineNo = 1; std::getline(in, line); ++lineNo) {
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag) || tag[0] == '#') continue;
    const std::string where = fmt::format("{}:{}", path, lineNo);
    if (tag == "v") {
      P3 p{};
      if (!readPoint(ls, p)) throw InputError(where + ": expected \"v x y z\", got \"" + line + "\"");
      if (!finite(p)) throw InputError(where + ": vertex coordinate is not a finite number");
      m.positions.push_back(p);
    } else if (tag == "f") {
      std::vector<uint32_t> face;
      std::string tok;
      while (ls >> tok) {
        long idx = 0;
        try {
          idx = std::stol(tok.substr(0, tok.find('/')));
        } catch (const std::exception&) {
          throw InputError(where + ": expected a vertex index, got \"" + tok + "\"");
        }
        const long n = long(m.positions.size());
        const long zeroBased = idx < 0 ? n + idx : idx - 1;
        if (idx == 0 || zeroBased < 0 || zeroBased >= n)
          throw InputError(fmt::format("{}: vertex index {} out of range (1..{} so far)", where, idx, n));
        face.push_back(uint32_t(zeroBased));
      }
      if (face.size() < 3) throw InputError(where + ": a face needs at least 3 vertices");
      for (size_t k = 1; k + 1 < face.size(); ++k) m.triangles.push_back({face[0], face[k], face[k + 1]});
    }
  }
  return m;
}

TriangleMesh readAsciiStl(const std::string& path, const std::string& text) {
  std::istringstream in(text);
  TriangleMesh m;
  std::string line;
  size_t corner = 0;
  for (size_t lineNo = 1; std::getline(in, line); ++lineNo) {
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag) || tag != "vertex") continue;
    P3 p{};
    const std::string where = fmt::format("{}:{}", path, lineNo);
    if (!readPoint(ls, p)) throw InputError(where + ": expected \"vertex x y z\"");
    if (!finite(p)) throw InputError(where + ": vertex coordinate is not a finite number");
    m.positions.push_back(p);
    if (++corner % 3 == 0) {
      const uint32_t b = uint32_t(m.positions.size() - 3);
      m.triangles.push_back({b, b + 1, b + 2});
    }
  }
  if (corner % 3 != 0) throw InputError(path + ": the last facet has fewer than 3 vertices");
  return m;
}

TriangleMesh readBinaryStl(const std::string& path, const std::string& bytes) {
  uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  TriangleMesh m;
  for (uint32_t t = 0; t < n; ++t) {
    const char* rec = bytes.data() + 84 + size_t(t) * 50 + 12;  // after the facet normal
    for (int c = 0; c < 3; ++c) {
      P3 p{};
      std::memcpy(p.data(), rec + 12 * c, 12);
      if (!finite(p))
        throw InputError(fmt::format("{}: triangle {}: vertex coordinate is not a finite number", path, t));
      m.positions.push_back(p);
    }
    const uint32_t b = 3 * t;
    m.triangles.push_back({b, b + 1, b + 2});
  }
  return m;
}

// Binary STL: an 80-byte header, a triangle count and 50 bytes per triangle; a file of exactly that size
// is binary even if its header starts with "solid" (many exporters write that).
TriangleMesh readStl(const std::string& path) {
  const std::string bytes = readTextFile(path);
  if (bytes.size() >= 84) {
    uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    if (bytes.size() == 84 + size_t(n) * 50) return readBinaryStl(path, bytes);
  }
  if (bytes.rfind("solid", 0) != 0)
    throw InputError(path + ": neither binary STL (size 84 + 50 n) nor ASCII STL (starting \"solid\")");
  return readAsciiStl(path, bytes);
}

void place(TriangleMesh& m, const Collider& c) {
  const Quat q = quatFromEulerDegrees(c.rotation);
  for (auto& p : m.positions) {
    const Vec3d r = rotate(q, {c.scale * p[0], c.scale * p[1], c.scale * p[2]});
    for (int a = 0; a < 3; ++a) p[a] = float(r[a] + c.translation[a]);
  }
}

openvdb::FloatGrid::Ptr readLevelSet(const Collider& c) {
  openvdb::initialize();
  openvdb::io::File file(c.file);
  try {
    file.open();
  } catch (const openvdb::Exception& e) {
    throw InputError(c.file + ": not a readable OpenVDB file (" + e.what() + ")");
  }
  openvdb::GridBase::Ptr base;
  std::string names;
  for (auto it = file.beginName(); it != file.endName(); ++it) {
    openvdb::GridBase::Ptr g = file.readGridMetadata(it.gridName());
    names += (names.empty() ? "" : ", ") + it.gridName();
    const bool wanted = c.grid.empty() ? g->isType<openvdb::FloatGrid>() : it.gridName() == c.grid;
    if (wanted && !base) base = file.readGrid(it.gridName());
  }
  file.close();
  const std::string which = c.grid.empty() ? "a float grid" : "grid \"" + c.grid + "\"";
  if (!base)
    throw InputError(fmt::format("{}: no {} (grids: {})", c.file, which, names.empty() ? "none" : names));
  auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  if (!grid)
    throw InputError(fmt::format("{}: grid \"{}\" is a {} grid, expected a float level set", c.file,
                                 base->getName(), base->valueType()));
  if (grid->getGridClass() == openvdb::GRID_FOG_VOLUME)
    throw InputError(fmt::format("{}: grid \"{}\" is a fog volume, expected a level set (negative inside)",
                                 c.file, grid->getName()));
  if (grid->activeVoxelCount() == 0)
    throw InputError(fmt::format("{}: grid \"{}\" is empty", c.file, grid->getName()));
  return grid;
}

TriangleMesh meshLevelSet(const Collider& c) {
  const openvdb::FloatGrid::Ptr grid = readLevelSet(c);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  std::vector<openvdb::Vec4I> quads;
  openvdb::tools::volumeToMesh(*grid, points, tris, quads, 0.0, 0.0);
  TriangleMesh m;
  for (const auto& p : points) m.positions.push_back({p.x(), p.y(), p.z()});
  // volumeToMesh winds its polygons the opposite way to the outward normal convention: flip.
  for (const auto& t : tris) m.triangles.push_back({t[0], t[2], t[1]});
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[2], q[1]});
    m.triangles.push_back({q[0], q[3], q[2]});
  }
  if (m.triangles.empty())
    throw InputError(
        fmt::format("{}: grid \"{}\" has no zero crossing (no surface)", c.file, grid->getName()));
  return m;
}

std::string fieldKey(const Collider& c, const FieldSpec& spec) {
  const std::string params = fmt::format("v1 {} {} {} {} [{},{},{}] [{},{},{}] {} {} {} {}", int(c.shape),
                                         c.grid, c.scale, c.thickness, c.rotation[0], c.rotation[1],
                                         c.rotation[2], c.translation[0], c.translation[1], c.translation[2],
                                         spec.voxel, spec.interiorDepth, spec.exteriorBand, c.file);
  return fmt::format("{:016x}", fnv1a64(params, fnv1a64(readTextFile(c.file))));
}

std::string openMeshMessage(size_t index, const Collider& c, size_t open) {
  return fmt::format(
      "/colliders/{}: {}: the mesh is not closed ({} open edges); close it or give "
      "\"thickness\" to make it a shell",
      index, c.file, open);
}

// The placed rest mesh, errors prefixed with the collider's JSON path.
TriangleMesh placedMesh(const Collider& c, size_t index) {
  try {
    return colliderRestMesh(c);
  } catch (const InputError& e) {
    throw InputError(fmt::format("/colliders/{}: {}", index, e.what()));
  }
}

openvdb::FloatGrid::Ptr distanceGrid(const TriangleMesh& m, const Collider& c, size_t index,
                                     const FieldSpec& spec, float& shift) {
  const auto xform = openvdb::math::Transform::createLinearTransform(spec.voxel);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> tris;
  for (const auto& p : m.positions) points.emplace_back(p[0], p[1], p[2]);
  for (const auto& t : m.triangles) tris.emplace_back(t[0], t[1], t[2]);
  const float ex = float(spec.exteriorBand / spec.voxel) + 1, in = float(spec.interiorDepth / spec.voxel) + 1;
  shift = 0;
  const size_t open = c.shape == Shape::Mesh ? countOpenEdges(m) : 0;
  if (open == 0)
    return openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(*xform, points, tris, {}, ex, in);
  if (!(c.thickness > 0)) throw InputError(openMeshMessage(index, c, open));
  // A shell: the unsigned distance less half the thickness is a signed distance of the thick surface.
  shift = float(0.5 * c.thickness);
  return openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(
      *xform, points, tris, {}, std::max(ex, in) + shift / float(spec.voxel));
}

ColliderField densify(const openvdb::FloatGrid& grid, float shift, size_t index, const Collider& c) {
  openvdb::CoordBBox bb = grid.evalActiveVoxelBoundingBox();
  bb.expand(1);
  const openvdb::Coord dim = bb.dim();
  const size_t n = size_t(dim.x()) * size_t(dim.y()) * size_t(dim.z());
  if (n > kMaxColliderFieldVoxels)
    throw InputError(
        fmt::format("/colliders/{}: {}: its distance field would take {} x {} x {} voxels of {} m, "
                    "more than {}; coarsen fluid.spacing, scale the geometry or split it",
                    index, c.file, dim.x(), dim.y(), dim.z(), grid.voxelSize()[0], kMaxColliderFieldVoxels));
  ColliderField f;
  f.voxel = grid.voxelSize()[0];
  f.dims = {dim.x(), dim.y(), dim.z()};
  const openvdb::Vec3d o = grid.transform().indexToWorld(bb.min());
  f.origin = {o.x(), o.y(), o.z()};
  f.distance.resize(n);
  auto acc = grid.getConstAccessor();
  size_t i = 0;
  for (int z = bb.min().z(); z <= bb.max().z(); ++z)
    for (int y = bb.min().y(); y <= bb.max().y(); ++y)
      for (int x = bb.min().x(); x <= bb.max().x(); ++x) f.distance[i++] = acc.getValue({x, y, z}) - shift;
  return f;
}

void setSolidBounds(ColliderField& f, const TriangleMesh& m, double grow) {
  f.solidMin = {1e300, 1e300, 1e300};
  f.solidMax = {-1e300, -1e300, -1e300};
  for (const auto& p : m.positions)
    for (int a = 0; a < 3; ++a) {
      f.solidMin[a] = std::min(f.solidMin[a], double(p[a]) - grow);
      f.solidMax[a] = std::max(f.solidMax[a], double(p[a]) + grow);
    }
}

openvdb::Vec3d asVdb(const std::array<double, 3>& v) {
  return {v[0], v[1], v[2]};
}

// A cached field: the narrow-band grid with the key and the solid bounds as metadata.
bool readCached(const std::string& path, const std::string& key, openvdb::FloatGrid::Ptr& grid, float& shift,
                std::array<double, 3>& lo, std::array<double, 3>& hi) {
  std::error_code ec;
  if (path.empty() || !std::filesystem::is_regular_file(path, ec)) return false;
  try {
    openvdb::io::File file(path);
    file.open();
    grid = openvdb::gridPtrCast<openvdb::FloatGrid>(file.readGrid("distance"));
    file.close();
    if (!grid || grid->metaValue<std::string>("sphfx_key") != key) return false;
    shift = grid->metaValue<float>("sphfx_shift");
    const openvdb::Vec3d a = grid->metaValue<openvdb::Vec3d>("sphfx_solid_min"),
                         b = grid->metaValue<openvdb::Vec3d>("sphfx_solid_max");
    lo = {a.x(), a.y(), a.z()};
    hi = {b.x(), b.y(), b.z()};
    return true;
  } catch (const openvdb::Exception&) {
    return false;  // unreadable or from another version: rebuilt and overwritten
  }
}

}  // namespace

TriangleMesh readColliderMesh(const std::string& path) {
  const std::string ext = lowerExtension(path);
  TriangleMesh m;
  if (ext == ".obj")
    m = readObj(path);
  else if (ext == ".stl")
    m = readStl(path);
  else if (ext == ".ply")
    m = readPly(path);
  else
    throw InputError(path + ": unknown mesh format \"" + ext + "\" (expected .obj, .ply or .stl)");
  if (ext == ".ply")
    for (size_t i = 0; i < m.positions.size(); ++i)
      if (!finite(m.positions[i]))
        throw InputError(fmt::format("{}: vertex {}: coordinate is not a finite number", path, i));
  if (m.triangles.empty()) throw InputError(path + ": no triangles");
  computeVertexNormals(m);
  return m;
}

size_t countOpenEdges(const TriangleMesh& m) {
  // Vertices closer than a millionth of the mesh's extent are one (exporters that duplicate vertices
  // per facet, as STL does, may round a seam's copies differently).
  float extent = 0;
  for (int a = 0; a < 3; ++a) {
    float lo = INFINITY, hi = -INFINITY;
    for (const auto& p : m.positions) lo = std::min(lo, p[a]), hi = std::max(hi, p[a]);
    if (!m.positions.empty()) extent = std::max(extent, hi - lo);
  }
  const double cell = std::max(1e-6 * double(extent), 1e-30);
  std::map<std::array<long long, 3>, uint32_t> weld;
  std::vector<uint32_t> id(m.positions.size());
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const auto& p = m.positions[i];
    const std::array<long long, 3> key{std::llround(p[0] / cell), std::llround(p[1] / cell),
                                       std::llround(p[2] / cell)};
    id[i] = weld.emplace(key, uint32_t(weld.size())).first->second;
  }
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (const auto& t : m.triangles)
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = id[t[e]], b = id[t[(e + 1) % 3]];
      if (a != b) ++uses[{std::min(a, b), std::max(a, b)}];
    }
  size_t open = 0;
  for (const auto& [edge, n] : uses) open += n == 1;
  return open;
}

TriangleMesh colliderRestMesh(const Collider& c) {
  if (!c.isField()) throw InputError("colliderRestMesh: an analytic collider has no mesh file");
  TriangleMesh m = c.shape == Shape::Mesh ? readColliderMesh(c.file) : meshLevelSet(c);
  place(m, c);
  computeVertexNormals(m);
  return m;
}

FieldSpec colliderFieldSpec(const Scene& scene) {
  const double s = scene.fluid.spacing;
  return {0.5 * s, scene.kernelRadius() + s, s};
}

std::string colliderFieldPath(const std::string& shotDir, size_t index) {
  return fmt::format("{}/colliders/collider.{}.vdb", shotDir, index);
}

std::vector<size_t> checkColliderGeometry(const Scene& scene) {
  std::vector<size_t> triangles;
  for (size_t i = 0; i < scene.colliders.size(); ++i) {
    const Collider& c = scene.colliders[i];
    if (!c.isField()) {
      triangles.push_back(0);
      continue;
    }
    const TriangleMesh m = placedMesh(c, i);
    if (c.shape == Shape::Mesh && !(c.thickness > 0))
      if (const size_t open = countOpenEdges(m)) throw InputError(openMeshMessage(i, c, open));
    triangles.push_back(m.triangles.size());
  }
  return triangles;
}

double ColliderField::sample(const Vec3d& p) const {
  double g[3], outside2 = 0;
  int i0[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    g[a] = (p[a] - origin[a]) / voxel;
    const double c = std::clamp(g[a], 0.0, double(dims[a] - 1));
    outside2 += (g[a] - c) * (g[a] - c);
    i0[a] = std::min(int(c), dims[a] - 2);
    t[a] = c - i0[a];
  }
  auto at = [&](int x, int y, int z) { return double(distance[(size_t(z) * dims[1] + y) * dims[0] + x]); };
  double d = 0;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
    const double w = (dx ? t[0] : 1 - t[0]) * (dy ? t[1] : 1 - t[1]) * (dz ? t[2] : 1 - t[2]);
    d += w * at(i0[0] + dx, i0[1] + dy, i0[2] + dz);
  }
  return d + std::sqrt(outside2) * voxel;
}

ColliderField buildColliderField(const Collider& c, size_t index, const FieldSpec& spec,
                                 const std::string& cacheFile, bool* rebuilt) {
  if (!c.isField()) throw InputError(fmt::format("/colliders/{}: an analytic collider has no field", index));
  openvdb::initialize();
  const std::string key = fieldKey(c, spec);
  openvdb::FloatGrid::Ptr grid;
  float shift = 0;
  std::array<double, 3> lo{}, hi{};
  const bool cached = readCached(cacheFile, key, grid, shift, lo, hi);
  if (rebuilt) *rebuilt = !cached;
  if (cached) {
    ColliderField f = densify(*grid, shift, index, c);
    f.solidMin = lo;
    f.solidMax = hi;
    return f;
  }
  const TriangleMesh m = placedMesh(c, index);
  grid = distanceGrid(m, c, index, spec, shift);
  ColliderField f = densify(*grid, shift, index, c);
  setSolidBounds(f, m, shift);
  if (!cacheFile.empty()) {
    grid->setName("distance");
    grid->insertMeta("sphfx_key", openvdb::StringMetadata(key));
    grid->insertMeta("sphfx_shift", openvdb::FloatMetadata(shift));
    grid->insertMeta("sphfx_solid_min", openvdb::Vec3DMetadata(asVdb(f.solidMin)));
    grid->insertMeta("sphfx_solid_max", openvdb::Vec3DMetadata(asVdb(f.solidMax)));
    std::filesystem::create_directories(std::filesystem::path(cacheFile).parent_path());
    writeVdbFile(cacheFile, {grid});
  }
  return f;
}

}  // namespace sphfx
