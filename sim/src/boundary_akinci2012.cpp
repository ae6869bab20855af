#include "boundary_akinci2012.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "bindings.h"
#include "gpu_types.h"
#include "sim_shaders.h"
#include "sphfx/core/collider_motion.h"
#include "sphfx/core/log.h"
#include "sphfx/gpu/gl.h"

namespace sphfx::sim {
namespace {

using P3 = std::array<double, 3>;
}  // namespace

// Boundary samples continue the fluid's cubic lattice into the solid, `layers` deep, each standing for
// its lattice cell: psi_b = m * (cell volume / s^3), with m the calibrated particle mass. A fluid particle
// of the initial lattice next to a flat wall (or in a corner) then sees exactly the neighbourhood it
// would see inside the fluid, so it starts at rest density. A single surface layer with Akinci's
// psi = rho0 / sum_k W_bk cannot do that at h = 2 s: it overshoots by ~40 % half a spacing from the
// wall, and scaling psi down to fix the lattice makes the wall too soft once particles approach it
// (measured: hydrostatic column sank 14 %, wall densities 800-960 kg/m^3; docs/simulation.md).
int boundaryLayers(const Scene& scene) {
  return std::max(1, int(std::ceil(scene.kernelRadius() / scene.fluid.spacing - 1e-9)));
}

namespace {

// Cells of [lo, hi] per axis, about `spacing` wide (exact fit per axis).
std::array<int, 3> latticeCells(const P3& lo, const P3& hi, double spacing) {
  std::array<int, 3> n{};
  for (int a = 0; a < 3; ++a) n[a] = std::max(1, int(std::lround((hi[a] - lo[a]) / spacing)));
  return n;
}

// Cell centres of the lattice over [lo, hi] with index range [-outer[a], n[a] + outer[a]) per axis, kept
// where `keep` (given the index) says so.
template <class Keep>
void appendLattice(const P3& lo, const P3& hi, const std::array<int, 3>& n, const std::array<int, 3>& outer,
                   double psiPerVolume, uint32_t body, BoundarySamples& out, Keep keep) {
  P3 step{};
  for (int a = 0; a < 3; ++a) step[a] = (hi[a] - lo[a]) / double(n[a]);
  const double psi = psiPerVolume * step[0] * step[1] * step[2];
  for (int k = -outer[2]; k < n[2] + outer[2]; ++k)
    for (int j = -outer[1]; j < n[1] + outer[1]; ++j)
      for (int i = -outer[0]; i < n[0] + outer[0]; ++i) {
        if (!keep(std::array<int, 3>{i, j, k})) continue;
        out.rest.push_back({float(lo[0] + (i + 0.5) * step[0]), float(lo[1] + (j + 0.5) * step[1]),
                            float(lo[2] + (k + 0.5) * step[2]), float(psi)});
        out.body.push_back(body);
      }
}

// Shells of a solid sphere at radii r - (l + 1/2) s, Fibonacci lattices (near-uniform, no poles) with
// one sample per s^2 of shell area; each sample stands for its share of the shell's volume.
void appendSphere(const P3& c, double r, double s, int layers, double psiPerVolume, uint32_t body,
                  BoundarySamples& out) {
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int l = 0; l < layers; ++l) {
    const double rl = r - (l + 0.5) * s;
    if (rl < 0.5 * s) {  // the core: one sample for the remaining ball
      const double core = std::max(r - l * s, 0.0);
      out.rest.push_back({float(c[0]), float(c[1]), float(c[2]),
                          float(psiPerVolume * 4.0 / 3.0 * std::numbers::pi * core * core * core)});
      out.body.push_back(body);
      return;
    }
    const double area = 4.0 * std::numbers::pi * rl * rl;
    const int n = std::max(1, int(std::lround(area / (s * s))));
    for (int i = 0; i < n; ++i) {
      const double y = 1.0 - 2.0 * (double(i) + 0.5) / double(n), rad = std::sqrt(1.0 - y * y);
      const double phi = golden * double(i);
      out.rest.push_back({float(c[0] + rl * rad * std::cos(phi)), float(c[1] + rl * y),
                          float(c[2] + rl * rad * std::sin(phi)), float(psiPerVolume * area * s / n)});
      out.body.push_back(body);
    }
  }
}

}  // namespace

ColliderFields buildColliderFields(const Scene& scene, const std::string& shotDir) {
  ColliderFields fields(scene.colliders.size());
  const FieldSpec spec = colliderFieldSpec(scene);
  for (size_t c = 0; c < scene.colliders.size(); ++c) {
    const Collider& col = scene.colliders[c];
    if (!col.isField()) continue;
    const auto t0 = std::chrono::steady_clock::now();
    bool rebuilt = true;
    const std::string cache = shotDir.empty() ? "" : colliderFieldPath(shotDir, c);
    fields[c] = buildColliderField(col, c, spec, cache, &rebuilt);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& d = fields[c].dims;
    logInfo(fmt::format("collider {} ({}): distance field {} x {} x {} voxels of {} m, {} in {:.2f} s", c,
                        col.name.empty() ? col.file : col.name, d[0], d[1], d[2], spec.voxel,
                        rebuilt ? "built" : "read from the shot", sec));
  }
  return fields;
}

namespace {
// Mesh and vdb colliders: the cell centres of the lattice over the solid's bounds (exact fit per axis,
// as a box) that lie inside the surface, less than `layers` spacings deep.
void appendField(const ColliderField& f, double s, int layers, double psiPerVolume, uint32_t body,
                 BoundarySamples& out) {
  const std::array<int, 3> m = latticeCells(f.solidMin, f.solidMax, s);
  const double depth = layers * s;
  appendLattice(f.solidMin, f.solidMax, m, {0, 0, 0}, psiPerVolume, body, out,
                [&](const std::array<int, 3>& idx) {
                  Vec3d p{};
                  for (int a = 0; a < 3; ++a)
                    p[a] = f.solidMin[a] + (idx[a] + 0.5) * (f.solidMax[a] - f.solidMin[a]) / double(m[a]);
                  const double d = f.sample(p);
                  return d <= 0 && d > -depth;
                });
}
}  // namespace

void warnIfWallLatticeMisfits(const Scene& scene) {
  const double s = scene.fluid.spacing;
  std::string axes;
  for (int a = 0; a < 3; ++a) {
    bool touches = false;  // a block of fluid against one of the axis' walls
    for (const FluidBlock& b : scene.fluid.blocks) {
      const double lo = b.shape == Shape::Box ? b.min[a] : b.center[a] - b.radius;
      const double hi = b.shape == Shape::Box ? b.max[a] : b.center[a] + b.radius;
      touches = touches || lo - scene.domain.min[a] < s || scene.domain.max[a] - hi < s;
    }
    if (scene.domain.isPeriodic(a) || !touches) continue;
    const double extent = scene.domain.max[a] - scene.domain.min[a], n = extent / s;
    if (std::fabs(n - std::round(n)) <= 0.01) continue;
    axes += fmt::format("{}{} {} m is {:.2f} spacings (walls {:.5g} m apart)", axes.empty() ? "" : "; ",
                        "xyz"[a], extent, n, extent / std::max(1.0, std::round(n)));
  }
  if (axes.empty()) return;
  logWarning(
      fmt::format("domain extent not a whole number of fluid.spacing {} m: {}. The fluid next to those "
                  "walls starts off its rest density and splashes in the first frames; a spacing "
                  "that divides the extents avoids it",
                  s, axes));
}

BoundarySamples sampleBoundaries(const Scene& scene, const ColliderFields& fields) {
  BoundarySamples out;
  const double s = scene.fluid.spacing;
  const int layers = boundaryLayers(scene);
  // psi per unit volume: the lattice cell s^3 weighs the calibrated particle mass.
  const double psiPerVolume = calibratedParticleMass(scene) / (s * s * s);
  // Domain walls: the shell of `layers` lattice cells around the domain (edges and corners included).
  // Periodic axes have no walls: the shell spans only [min, max) along them and the solver passes see
  // its samples across the seam.
  const std::array<int, 3> n = latticeCells(scene.domain.min, scene.domain.max, s);
  std::array<int, 3> outer{};
  for (int a = 0; a < 3; ++a) outer[a] = scene.domain.isPeriodic(a) ? 0 : layers;
  appendLattice(scene.domain.min, scene.domain.max, n, outer, psiPerVolume, BoundarySamples::kWallBody, out,
                [&](const std::array<int, 3>& idx) {
                  for (int a = 0; a < 3; ++a)
                    if (idx[a] < 0 || idx[a] >= n[a]) return true;
                  return false;
                });
  for (size_t c = 0; c < scene.colliders.size(); ++c) {
    const Collider& col = scene.colliders[c];
    if (col.shape == Shape::Box) {
      // The inner shell, `layers` cells deep, of the box's own lattice.
      const std::array<int, 3> m = latticeCells(col.min, col.max, s);
      appendLattice(col.min, col.max, m, {0, 0, 0}, psiPerVolume, uint32_t(c), out,
                    [&](const std::array<int, 3>& idx) {
                      for (int a = 0; a < 3; ++a)
                        if (idx[a] < layers || idx[a] >= m[a] - layers) return true;
                      return false;
                    });
    } else if (col.shape == Shape::Sphere) {
      appendSphere(col.center, col.radius, s, layers, psiPerVolume, uint32_t(c), out);
    } else {
      if (c >= fields.size() || fields[c].distance.empty())
        throw std::logic_error("sampleBoundaries: no field for collider " + std::to_string(c));
      appendField(fields[c], s, layers, psiPerVolume, uint32_t(c), out);
    }
  }
  return out;
}

namespace {
// The collider table, three vec4 per key (time and offset; rotation quaternion xyzw; the angular
// velocity of the segment that starts at the key) and the fields' values one after the other.
std::vector<ColliderGpu> colliderTable(const Scene& scene, const ColliderFields& fields,
                                       std::vector<std::array<float, 4>>& keys, std::vector<float>& values) {
  std::vector<ColliderGpu> table;
  for (size_t i = 0; i < scene.colliders.size(); ++i) {
    const Collider& c = scene.colliders[i];
    ColliderGpu g{};
    const Vec3d pivot = colliderPivot(c);
    for (int a = 0; a < 3; ++a) g.pivot[a] = float(pivot[a]);
    if (c.shape == Shape::Box) {
      for (int a = 0; a < 3; ++a) g.shapeA[a] = float(c.min[a]), g.shapeB[a] = float(c.max[a]);
      g.info[0] = 0;
    } else if (c.shape == Shape::Sphere) {
      for (int a = 0; a < 3; ++a) g.shapeA[a] = float(c.center[a]);
      g.shapeA[3] = float(c.radius);
      g.info[0] = 1;
    } else {
      const ColliderField& f = fields.at(i);
      for (int a = 0; a < 3; ++a) g.shapeA[a] = float(f.origin[a]), g.shapeB[a] = float(f.dims[a]);
      g.shapeA[3] = float(f.voxel);
      g.info[0] = 2;
      g.info[3] = uint32_t(values.size());
      values.insert(values.end(), f.distance.begin(), f.distance.end());
    }
    g.info[1] = uint32_t(keys.size() / 3);
    g.info[2] = uint32_t(c.keyframes.size());
    for (size_t k = 0; k < c.keyframes.size(); ++k) {
      const Keyframe& key = c.keyframes[k];
      const Quat q = quatFromEulerDegrees(key.rotation);
      // The segment's angular velocity, as colliderPose() turns it (0 after the last key).
      const ColliderPose pose = colliderPose(
          c, k + 1 < c.keyframes.size() ? 0.5 * (key.time + c.keyframes[k + 1].time) : key.time + 1);
      const Vec3d w = k + 1 < c.keyframes.size() ? pose.angularVelocity : Vec3d{0, 0, 0};
      keys.push_back({float(key.time), float(key.offset[0]), float(key.offset[1]), float(key.offset[2])});
      keys.push_back({float(q.x), float(q.y), float(q.z), float(q.w)});
      keys.push_back({float(w[0]), float(w[1]), float(w[2]), 0.0f});
    }
    table.push_back(g);
  }
  return table;
}

template <class T>
GpuBuffer makeBuffer(const std::vector<T>& v) {
  GpuBuffer b(std::max<size_t>(v.size(), 1) * sizeof(T));
  if (!v.empty()) b.upload(v.data(), v.size() * sizeof(T));
  return b;
}
}  // namespace

BoundaryAkinci2012::BoundaryAkinci2012(const Scene& scene, const ColliderFields& fields, DispatchGate& gate,
                                       const GridSpec& grid, const ShaderDefines& defines)
    : gate_(&gate), moving_(!scene.colliders.empty()) {
  const BoundarySamples samples = sampleBoundaries(scene, fields);
  count_ = uint32_t(samples.size());
  rest_ = makeBuffer(samples.rest);
  body_ = makeBuffer(samples.body);
  std::vector<std::array<float, 4>> keys;
  std::vector<float> values;
  colliders_ = makeBuffer(colliderTable(scene, fields, keys, values));
  keys_ = makeBuffer(keys);
  field_ = makeBuffer(values);
  unsortedPos_ = makeBuffer(samples.rest);
  unsortedVel_ = makeBuffer(std::vector<std::array<float, 4>>(samples.size(), {0, 0, 0, 0}));
  pos_.resize(size_t(count_) * 16);
  vel_.resize(size_t(count_) * 16);
  grid_ = std::make_unique<NeighborGrid>(gate, grid, count_);
  entry_ = gate.add(count_, kSimWorkGroup);
  if (moving_) update_ = ShaderProgram::compute(simShaderTable(), "sim_boundary_update.comp", defines);
}

void BoundaryAkinci2012::sort() const {
  grid_->build(unsortedPos_, unsortedVel_, pos_, vel_);
}

void BoundaryAkinci2012::update() const {
  if (!moving_) return;
  rest_.bindStorage(SPHFX_SSBO_SIM_BOUNDARY_REST);
  body_.bindStorage(SPHFX_SSBO_SIM_BOUNDARY_BODY);
  colliders_.bindStorage(SPHFX_SSBO_SIM_COLLIDERS);
  keys_.bindStorage(SPHFX_SSBO_SIM_COLLIDER_KEYS);
  unsortedPos_.bindStorage(SPHFX_SSBO_SIM_UNSORTED_POS);
  unsortedVel_.bindStorage(SPHFX_SSBO_SIM_UNSORTED_VEL);
  update_.use();
  gate_->dispatch(entry_, "sim_boundary_update.comp");
  storageBarrier();
  sort();
}

void BoundaryAkinci2012::prepare() const {
  if (moving_)
    update();
  else
    sort();
}

void BoundaryAkinci2012::bind() const {
  pos_.bindStorage(SPHFX_SSBO_SIM_BOUNDARY_POS);
  vel_.bindStorage(SPHFX_SSBO_SIM_BOUNDARY_VEL);
  grid_->rowStart().bindStorage(SPHFX_SSBO_SIM_BOUNDARY_CELL_START);
  pos_.bindTexture(SPHFX_TEX_SIM_BOUNDARY_POS, GL_RGBA32F);
  vel_.bindTexture(SPHFX_TEX_SIM_BOUNDARY_VEL, GL_RGBA32F);
  grid_->rowStart().bindTexture(SPHFX_TEX_SIM_BOUNDARY_CELL_START, GL_R32UI);
  colliders_.bindStorage(SPHFX_SSBO_SIM_COLLIDERS);
  keys_.bindStorage(SPHFX_SSBO_SIM_COLLIDER_KEYS);
  field_.bindStorage(SPHFX_SSBO_SIM_COLLIDER_FIELD);
}

}  // namespace sphfx::sim
