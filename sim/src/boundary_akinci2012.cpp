#include "sphfx/sim/boundary_akinci2012.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "bindings.h"
#include "sphfx/core/gl.h"
#include "sphfx/sim/gpu_types.h"

namespace sphfx::sim {
namespace {

using P3 = std::array<double, 3>;

// Lattice points on the surface of the box [lo, hi], about `spacing` apart (exact fit per axis).
void sampleBoxSurface(const P3& lo, const P3& hi, double spacing, std::vector<P3>& out) {
  std::array<int, 3> n{};
  for (int a = 0; a < 3; ++a) n[a] = std::max(1, int(std::lround((hi[a] - lo[a]) / spacing)));
  for (int i = 0; i <= n[0]; ++i)
    for (int j = 0; j <= n[1]; ++j)
      for (int k = 0; k <= n[2]; ++k) {
        const bool surface = i == 0 || j == 0 || k == 0 || i == n[0] || j == n[1] || k == n[2];
        if (!surface) continue;
        const std::array<int, 3> idx{i, j, k};
        P3 p{};
        for (int a = 0; a < 3; ++a) p[a] = lo[a] + (hi[a] - lo[a]) * double(idx[a]) / double(n[a]);
        out.push_back(p);
      }
}

// Fibonacci lattice on a sphere: near-uniform spacing without poles.
void sampleSphereSurface(const P3& c, double r, double spacing, std::vector<P3>& out) {
  const int n = std::max(12, int(std::lround(4.0 * std::numbers::pi * r * r / (spacing * spacing))));
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = 1.0 - 2.0 * (double(i) + 0.5) / double(n), rad = std::sqrt(1.0 - y * y);
    const double phi = golden * double(i);
    out.push_back({c[0] + r * rad * std::cos(phi), c[1] + r * y, c[2] + r * rad * std::sin(phi)});
  }
}

// psi_b = rho0 / sum_k W(x_b - x_k) over the samples of one body (Akinci 2012, eq. 4-5).
std::vector<double> akinciPsi(const std::vector<P3>& pts, double h, double rho0) {
  const double poly6 = kernelFactors(h).poly6;
  auto key = [h](const P3& p, int dx, int dy, int dz) {
    return (int64_t(std::floor(p[0] / h)) + dx) * 73856093LL ^
           (int64_t(std::floor(p[1] / h)) + dy) * 19349663LL ^
           (int64_t(std::floor(p[2] / h)) + dz) * 83492791LL;
  };
  std::unordered_multimap<int64_t, size_t> cells;
  for (size_t i = 0; i < pts.size(); ++i) cells.emplace(key(pts[i], 0, 0, 0), i);
  std::vector<double> psi(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    double sum = 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto [b, e] = cells.equal_range(key(pts[i], dx, dy, dz));
          for (auto it = b; it != e; ++it) {
            const P3& q = pts[it->second];
            const double r2 = (pts[i][0] - q[0]) * (pts[i][0] - q[0]) +
                              (pts[i][1] - q[1]) * (pts[i][1] - q[1]) +
                              (pts[i][2] - q[2]) * (pts[i][2] - q[2]);
            if (r2 < h * h) sum += poly6 * std::pow(h * h - r2, 3);
          }
        }
    psi[i] = rho0 / sum;
  }
  return psi;
}

}  // namespace

double wallPsiScale(const Scene& scene) {
  // A fluid particle of the initial lattice half a spacing from a flat wall sampled one spacing apart:
  // fluid part F (half-space lattice) plus wall part B (Akinci psi of the plane). Akinci's psi makes a
  // single layer stand for the whole solid, which overshoots by ~40 % at h = 2 spacings with poly6;
  // scale psi so that F + scale * B = rho0, i.e. the initial lattice starts at rest at walls too.
  const double s = scene.fluid.spacing, h = scene.kernelRadius(), poly6 = kernelFactors(h).poly6;
  const double m = calibratedParticleMass(scene), rho0 = scene.fluid.restDensity;
  auto W = [&](double r2) { return r2 < h * h ? poly6 * std::pow(h * h - r2, 3) : 0.0; };
  const int n = int(std::ceil(h / s)) + 1;
  double fluid = 0, plane0 = 0, planeHalf = 0;
  for (int i = -n; i <= n; ++i)
    for (int k = -n; k <= n; ++k) {
      const double d2 = s * s * double(i * i + k * k);
      plane0 += W(d2);
      planeHalf += W(d2 + 0.25 * s * s);
      for (int j = 0; j <= n; ++j) fluid += m * W(d2 + s * s * double(j * j));
    }
  const double wall = rho0 / plane0 * planeHalf;
  return std::clamp((rho0 - fluid) / wall, 0.1, 1.0);
}

namespace {

void appendBody(BoundarySamples& out, const std::vector<P3>& pts, uint32_t body, const Scene& scene) {
  const std::vector<double> psi = akinciPsi(pts, scene.kernelRadius(), scene.fluid.restDensity);
  const double scale = wallPsiScale(scene);
  for (size_t i = 0; i < pts.size(); ++i) {
    out.rest.push_back({float(pts[i][0]), float(pts[i][1]), float(pts[i][2]), float(psi[i] * scale)});
    out.body.push_back(body);
  }
}

}  // namespace

BoundarySamples sampleBoundaries(const Scene& scene) {
  BoundarySamples out;
  const double s = scene.fluid.spacing;
  std::vector<P3> pts;
  sampleBoxSurface(scene.domain.min, scene.domain.max, s, pts);
  appendBody(out, pts, BoundarySamples::kWallBody, scene);
  for (size_t c = 0; c < scene.colliders.size(); ++c) {
    const Collider& col = scene.colliders[c];
    pts.clear();
    if (col.shape == Shape::Box)
      sampleBoxSurface(col.min, col.max, s, pts);
    else
      sampleSphereSurface(col.center, col.radius, s, pts);
    appendBody(out, pts, uint32_t(c), scene);
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
  if (moving_) update_ = ShaderProgram::compute("sim_boundary_update.comp", defines);
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
  grid_->cellStart().bindStorage(SPHFX_SSBO_SIM_BOUNDARY_CELL_START);
  colliders_.bindStorage(SPHFX_SSBO_SIM_COLLIDERS);
  keys_.bindStorage(SPHFX_SSBO_SIM_COLLIDER_KEYS);
}

}  // namespace sphfx::sim
