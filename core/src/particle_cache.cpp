#include "sphfx/core/particle_cache.h"

#include <fmt/format.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointCount.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <filesystem>
#include <memory>
#include <mutex>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/vdb_io.h"

namespace sphfx {
namespace {

namespace vp = openvdb::points;

void initOpenVdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

template <class T>
using Wrapper = vp::PointAttributeVector<T>;

template <class T, class Src>
void addAttribute(vp::PointDataGrid& grid, const openvdb::tools::PointIndexGrid& index, const char* name,
                  const std::vector<Src>& values) {
  std::vector<T> converted(values.begin(), values.end());
  vp::appendAttribute<T>(grid.tree(), name);
  Wrapper<T> wrapper(converted);
  vp::populateAttribute<vp::PointDataTree, openvdb::tools::PointIndexTree, Wrapper<T>>(
      grid.tree(), index.tree(), name, wrapper);
}

std::vector<openvdb::Vec3f> toVdb(const std::vector<std::array<float, 3>>& v) {
  std::vector<openvdb::Vec3f> out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = openvdb::Vec3f(v[i][0], v[i][1], v[i][2]);
  return out;
}

void checkLengths(const std::string& path, const ParticleFrame& f) {
  const size_t n = f.position.size();
  auto bad = [&](size_t m) { return m != n && m != 0; };
  if (f.velocity.size() != n || bad(f.density.size()) || bad(f.pressure.size()) || bad(f.id.size()))
    throw InputError(path + ": particle attribute arrays differ in length");
}

template <class T>
T metaValue(const openvdb::GridBase& grid, const char* name, const std::string& path) {
  auto m = grid.getMetadata<openvdb::TypedMetadata<T>>(name);
  if (!m)
    throw InputError(path + ": not an sphfx particle cache (no \"" + std::string(name) + "\" metadata)");
  return m->value();
}

}  // namespace

std::string particleCachePath(const std::string& shotDir, int frame) {
  return framePath((std::filesystem::path(shotDir) / "cache").string(), "particles", frame, "vdb");
}

void writeParticleCache(const std::string& path, const ParticleFrame& f) {
  initOpenVdb();
  checkLengths(path, f);
  const std::vector<openvdb::Vec3f> positions = toVdb(f.position);
  const Wrapper<openvdb::Vec3f> positionWrapper(positions);
  // About 8 points per voxel at rest: voxels of two particle spacings. Without a spacing, ask OpenVDB.
  const double voxelSize = f.particleSpacing > 0 ? 2.0 * f.particleSpacing
                           : positions.empty()   ? 1.0
                                                 : double(vp::computeVoxelSize(positionWrapper, 8));
  auto transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  auto index =
      openvdb::tools::createPointIndexGrid<openvdb::tools::PointIndexGrid>(positionWrapper, *transform);
  // Positions are stored uncompressed (NullCodec): the surfacing stage and the determinism tests need the
  // simulator's floats back, bit for bit up to the voxel-offset split.
  auto grid = vp::createPointDataGrid<vp::NullCodec, vp::PointDataGrid>(*index, positionWrapper, *transform);
  addAttribute<openvdb::Vec3f>(*grid, *index, "v", toVdb(f.velocity));
  if (!f.density.empty()) addAttribute<float>(*grid, *index, "density", f.density);
  if (!f.pressure.empty()) addAttribute<float>(*grid, *index, "pressure", f.pressure);
  if (!f.id.empty()) addAttribute<int32_t>(*grid, *index, "id", f.id);

  grid->setName("points");
  grid->insertMeta("sphfx_cache_version", openvdb::Int32Metadata(kParticleCacheVersion));
  grid->insertMeta("frame", openvdb::Int32Metadata(f.frame));
  grid->insertMeta("time", openvdb::DoubleMetadata(f.time));
  grid->insertMeta("particle_spacing", openvdb::DoubleMetadata(f.particleSpacing));
  grid->insertMeta("particle_count", openvdb::Int64Metadata(int64_t(f.size())));

  writeVdbFile(path, openvdb::GridCPtrVec{grid});
}

ParticleFrame readParticleCache(const std::string& path, CacheFields fields) {
  initOpenVdb();
  openvdb::GridBase::Ptr base;
  try {
    openvdb::io::File file(path);
    file.open();
    if (!file.hasGrid("points")) throw InputError(path + ": no grid named \"points\"");
    base = file.readGrid("points");
    file.close();
  } catch (const openvdb::Exception& e) {
    throw IoError(path + ": cannot read: " + e.what());
  }
  auto grid = openvdb::gridPtrCast<vp::PointDataGrid>(base);
  if (!grid) throw InputError(path + ": grid \"points\" is not a PointDataGrid");
  const int version = metaValue<int32_t>(*grid, "sphfx_cache_version", path);
  if (version != kParticleCacheVersion)
    throw InputError(
        fmt::format("{}: cache version {} is not the supported {}", path, version, kParticleCacheVersion));

  ParticleFrame f;
  f.frame = metaValue<int32_t>(*grid, "frame", path);
  f.time = metaValue<double>(*grid, "time", path);
  f.particleSpacing = metaValue<double>(*grid, "particle_spacing", path);

  // Each leaf's first point in the output, so that leaves are converted in parallel into the same
  // order as a serial walk (leaf by leaf, voxel by voxel).
  std::vector<const vp::PointDataTree::LeafNodeType*> leaves;
  std::vector<size_t> first;
  size_t count = 0;
  for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
    leaves.push_back(&*leaf);
    first.push_back(count);
    count += size_t(leaf->onPointCount());
  }
  if (leaves.empty()) return f;
  const auto& descriptor = leaves.front()->attributeSet().descriptor();
  if (descriptor.find("v") == vp::AttributeSet::INVALID_POS) throw InputError(path + ": no \"v\" attribute");
  const bool all = fields == CacheFields::All;
  auto has = [&](const char* name) { return all && descriptor.find(name) != vp::AttributeSet::INVALID_POS; };
  const bool hasDensity = has("density"), hasPressure = has("pressure"), hasId = has("id");
  f.position.resize(count);
  if (all) f.velocity.resize(count);
  if (hasDensity) f.density.resize(count);
  if (hasPressure) f.pressure.resize(count);
  if (hasId) f.id.resize(count);

  const openvdb::math::Transform& xform = grid->transform();
  // Attributes not asked for are never touched, so with delayed loading they are not even decompressed.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), 16), [&](const auto& r) {
    for (size_t l = r.begin(); l != r.end(); ++l) {
      const auto& leaf = *leaves[l];
      vp::AttributeHandle<openvdb::Vec3f> p(leaf.constAttributeArray("P"));
      std::unique_ptr<vp::AttributeHandle<openvdb::Vec3f>> v;
      std::unique_ptr<vp::AttributeHandle<float>> d, pr;
      std::unique_ptr<vp::AttributeHandle<int32_t>> id;
      if (all) v = std::make_unique<vp::AttributeHandle<openvdb::Vec3f>>(leaf.constAttributeArray("v"));
      if (hasDensity) d = std::make_unique<vp::AttributeHandle<float>>(leaf.constAttributeArray("density"));
      if (hasPressure)
        pr = std::make_unique<vp::AttributeHandle<float>>(leaf.constAttributeArray("pressure"));
      if (hasId) id = std::make_unique<vp::AttributeHandle<int32_t>>(leaf.constAttributeArray("id"));
      size_t n = first[l];
      for (auto it = leaf.beginIndexOn(); it; ++it, ++n) {
        const openvdb::Vec3d world = xform.indexToWorld(p.get(*it) + it.getCoord().asVec3d());
        f.position[n] = {float(world.x()), float(world.y()), float(world.z())};
        if (v) {
          const openvdb::Vec3f vel = v->get(*it);
          f.velocity[n] = {vel.x(), vel.y(), vel.z()};
        }
        if (d) f.density[n] = d->get(*it);
        if (pr) f.pressure[n] = pr->get(*it);
        if (id) f.id[n] = id->get(*it);
      }
    }
  });
  return f;
}

}  // namespace sphfx
