#include "boundary_akinci2012.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bindings.h"
#include "gpu_types.h"
#include "sim_shaders.h"
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

BoundarySamples sampleBoundaries(const Scene& scene) {
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
    } else {
      appendSphere(col.center, col.radius, s, layers, psiPerVolume, uint32_t(c), out);
    }
  }
  return out;
}

namespace {
std::vector<ColliderGpu> colliderTable(const Scene& scene, std::vector<std::array<float, 4>>& keys) {
  std::vector<ColliderGpu> table;
  for (const Collider& c : scene.colliders) {
    ColliderGpu g{};
    const bool box = c.shape == Shape::Box;
    for (int a = 0; a < 3; ++a) {
      g.shapeA[a] = float(box ? c.min[a] : c.center[a]);
      g.shapeB[a] = float(box ? c.max[a] : c.center[a]);
    }
    g.shapeA[3] = float(box ? 0.0 : c.radius);
    g.info[0] = box ? 0 : 1;
    g.info[1] = uint32_t(keys.size());
    g.info[2] = uint32_t(c.keyframes.size());
    for (const Keyframe& k : c.keyframes)
      keys.push_back({float(k.time), float(k.offset[0]), float(k.offset[1]), float(k.offset[2])});
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

BoundaryAkinci2012::BoundaryAkinci2012(const Scene& scene, DispatchGate& gate, const GridSpec& grid,
                                       const ShaderDefines& defines)
    : gate_(&gate), moving_(!scene.colliders.empty()) {
  const BoundarySamples samples = sampleBoundaries(scene);
  count_ = uint32_t(samples.size());
  rest_ = makeBuffer(samples.rest);
  body_ = makeBuffer(samples.body);
  std::vector<std::array<float, 4>> keys;
  colliders_ = makeBuffer(colliderTable(scene, keys));
  keys_ = makeBuffer(keys);
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
}

}  // namespace sphfx::sim
