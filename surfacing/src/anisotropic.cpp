// Yu & Turk (2013), "Reconstructing surfaces of particle-based fluids using anisotropic kernels".
//
// Determinism: every per-particle and per-block result is computed by one task from inputs visited in a
// fixed order (particles sorted by cell then index; kernels gathered block by block in a fixed order), so
// floating-point sums do not depend on how TBB splits the work. OpenVDB's fast sweeping (the band's
// distances) updates the voxels of one diagonal slice in parallel, each from neighbours in other slices.
#include "anisotropic.h"

#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/FastSweeping.h>
#include <openvdb/tools/LevelSetTracker.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <unordered_map>

#include "anisotropic_isa.h"
#include "band_distance.h"
#include "sphfx/core/error.h"

namespace sphfx::surfacing {
namespace {

using Vec3d = std::array<double, 3>;
using Mat3d = std::array<std::array<double, 3>, 3>;

// Normalisation of P(q2) = (1 - q2)^3 over the unit ball: its integral is 64 pi / 315.
constexpr double kKernelNorm = 315.0 / (64.0 * std::numbers::pi);
// Weighted variance per axis of a full ball of neighbours with w(r) = 1 - (r/h)^3: 0.15 h^2
// (integral of w r^4 over integral of w r^2, divided by 3). Yu & Turk's k_s makes this 1.
constexpr double kFullVariance = 0.15;

uint64_t packKey(int64_t x, int64_t y, int64_t z) {
  constexpr int64_t kBias = int64_t(1) << 20;
  return (uint64_t(x + kBias) << 42) | (uint64_t(y + kBias) << 21) | uint64_t(z + kBias);
}

/// Particles binned into cubic cells, sorted by cell then by index: a deterministic neighbour search.
class CellGrid {
 public:
  CellGrid(const std::vector<std::array<float, 3>>& p, double cellSize) : cell_(cellSize) {
    std::vector<std::pair<uint64_t, uint32_t>> keyed(p.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, p.size(), 4096), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) keyed[i] = {key(p[i]), uint32_t(i)};
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());  // keys are unique (index included): a total order
    order_.resize(keyed.size());
    for (size_t i = 0; i < keyed.size(); ++i) {
      order_[i] = keyed[i].second;
      if (i == 0 || keyed[i].first != keyed[i - 1].first) {
        ranges_[keyed[i].first] = {uint32_t(i), uint32_t(i)};
        cells_.push_back({coord(p[keyed[i].second]), uint32_t(i), uint32_t(i)});
      }
      ranges_[keyed[i].first].second = uint32_t(i + 1);
      cells_.back().end = uint32_t(i + 1);
    }
  }

  std::array<int64_t, 3> coord(const std::array<float, 3>& x) const {
    return {int64_t(std::floor(x[0] / cell_)), int64_t(std::floor(x[1] / cell_)),
            int64_t(std::floor(x[2] / cell_))};
  }
  uint64_t key(const std::array<float, 3>& x) const {
    const auto c = coord(x);
    return packKey(c[0], c[1], c[2]);
  }

  /// The occupied cells: a cell coordinate and its range in order().
  struct Cell {
    std::array<int64_t, 3> coord;
    uint32_t begin, end;
  };
  const std::vector<Cell>& cells() const { return cells_; }
  /// Particle indices, cell by cell.
  const std::vector<uint32_t>& order() const { return order_; }

  /// Calls f(j) for every particle j in the 27 cells around cell `c`, in a fixed order.
  template <class F>
  void forEachNear(const std::array<int64_t, 3>& c, F&& f) const {
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          auto it = ranges_.find(packKey(c[0] + dx, c[1] + dy, c[2] + dz));
          if (it == ranges_.end()) continue;
          for (uint32_t k = it->second.first; k < it->second.second; ++k) f(order_[k]);
        }
  }

 private:
  double cell_;
  std::vector<uint32_t> order_;
  std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> ranges_;
  std::vector<Cell> cells_;
};

/// Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations (fixed sweep limit, so the
/// result depends only on the input). Eigenvalues descending; vectors are the columns of `v`.
void symmetricEigen(Mat3d a, Vec3d& values, Mat3d& v) {
  v = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (int sweep = 0; sweep < 16; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off < 1e-30) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (std::abs(a[p][q]) < 1e-300) continue;
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // a = J^T a J
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  std::array<int, 3> idx{0, 1, 2};
  std::sort(idx.begin(), idx.end(),
            [&](int i, int j) { return a[i][i] > a[j][j] || (a[i][i] == a[j][j] && i < j); });
  Mat3d sorted{};
  for (int c = 0; c < 3; ++c) {
    values[c] = a[idx[c]][idx[c]];
    for (int r = 0; r < 3; ++r) sorted[r][c] = v[r][idx[c]];
  }
  v = sorted;
}

/// Kernel with axes `axes` (m) along the columns of `rot`.
AnisotropicKernel makeKernel(const Vec3d& center, const Mat3d& rot, const Vec3d& axes, double volume) {
  AnisotropicKernel k;
  k.center = {float(center[0]), float(center[1]), float(center[2])};
  const int pairs[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  for (int m = 0; m < 6; ++m) {
    double sum = 0;
    for (int a = 0; a < 3; ++a) sum += rot[pairs[m][0]][a] * rot[pairs[m][1]][a] / (axes[a] * axes[a]);
    k.metric[m] = float(sum);
  }
  k.weight = float(volume * kKernelNorm / (axes[0] * axes[1] * axes[2]));
  k.extent = float(std::max({axes[0], axes[1], axes[2]}));
  return k;
}

/// A cell's neighbour candidates (the particles of its 27 neighbour cells, in CellGrid's fixed order)
/// as floats relative to a point of the cell, structure of arrays, padded to whole rows of kLanes with
/// points far outside every kernel.
constexpr int kLanes = 8;
struct Candidates {
  std::vector<float> x, y, z;
  void clear() {
    x.clear();
    y.clear();
    z.clear();
  }
  void push(float a, float b, float c) {
    x.push_back(a);
    y.push_back(b);
    z.push_back(c);
  }
  void pad() {
    while (x.size() % kLanes) push(1e18f, 1e18f, 1e18f);
  }
};

/// Per-lane sums of the weight w = 1 - (r/h)^3 (r < h), the neighbour count and the first and second
/// moments of the offsets. Lane k sums candidates k, k + kLanes, ...: the same sums whatever the
/// vector width the compiler picks, and reduced in a fixed order afterwards.
struct LaneSums {
  alignas(32) float w[kLanes], n[kLanes], x[kLanes], y[kLanes], z[kLanes];
  alignas(32) float xx[kLanes], xy[kLanes], xz[kLanes], yy[kLanes], yz[kLanes], zz[kLanes];
};

inline __attribute__((always_inline)) void sumMoments(const Candidates& c, float px, float py, float pz,
                                                      float h, LaneSums& s) {
  const float h2 = h * h, invH = 1 / h;
  const Float8 zero = {}, one = zero + 1.f;
  Float8 w8 = zero, n8 = zero, x8 = zero, y8 = zero, z8 = zero;
  Float8 xx = zero, xy = zero, xz = zero, yy = zero, yz = zero, zz = zero;
  for (size_t j0 = 0; j0 < c.x.size(); j0 += kLanes) {
    const Float8 dx = load8(&c.x[j0]) - px, dy = load8(&c.y[j0]) - py, dz = load8(&c.z[j0]) - pz;
    const Float8 r2 = dx * dx + dy * dy + dz * dz;
    Float8 r;
    for (int k = 0; k < kLanes; ++k) r[k] = __builtin_sqrtf(r2[k]);  // sqrtps: built with -fno-math-errno
    r *= invH;
    const auto in = r2 < h2;
    const Float8 w = in ? one - r * r * r : zero;
    w8 += w;
    n8 += in ? one : zero;
    x8 += w * dx;
    y8 += w * dy;
    z8 += w * dz;
    xx += w * dx * dx;
    xy += w * dx * dy;
    xz += w * dx * dz;
    yy += w * dy * dy;
    yz += w * dy * dz;
    zz += w * dz * dz;
  }
  auto store = [](float(&out)[kLanes], Float8 v) { std::memcpy(out, &v, sizeof out); };
  store(s.w, w8), store(s.n, n8), store(s.x, x8), store(s.y, y8), store(s.z, z8);
  store(s.xx, xx), store(s.xy, xy), store(s.xz, xz), store(s.yy, yy), store(s.yz, yz), store(s.zz, zz);
}

// sumMoments compiled for the baseline and for AVX2 (simd.h); chosen once per call of
// computeAnisotropicKernels.
void sumMomentsBaseline(const Candidates& c, float px, float py, float pz, float h, LaneSums& s) {
  sumMoments(c, px, py, pz, h, s);
}
SPHFX_TARGET_AVX2 void sumMomentsAvx2(const Candidates& c, float px, float py, float pz, float h,
                                      LaneSums& s) {
  sumMoments(c, px, py, pz, h, s);
}

double laneTotal(const float (&v)[kLanes]) {
  double t = 0;
  for (float x : v) t += x;
  return t;
}

/// The kernel of the particle at `xi` from its neighbourhood's lane sums (offsets relative to xi).
AnisotropicKernel kernelFor(const std::array<float, 3>& xi, const LaneSums& sums,
                            const AnisotropicSettings& s) {
  const double h = s.support, h2 = h * h;
  const double wsum = laneTotal(sums.w);
  const int neighbours = int(laneTotal(sums.n)) - 1;  // less the particle itself
  const Vec3d m1{laneTotal(sums.x), laneTotal(sums.y), laneTotal(sums.z)};
  const double xy = laneTotal(sums.xy), xz = laneTotal(sums.xz), yz = laneTotal(sums.yz);
  const Mat3d m2{{{laneTotal(sums.xx), xy, xz}, {xy, laneTotal(sums.yy), yz}, {xz, yz, laneTotal(sums.zz)}}};
  Vec3d mean{}, center{};
  for (int a = 0; a < 3; ++a) {
    mean[a] = m1[a] / wsum;
    center[a] = xi[a] + s.lambda * mean[a];  // (1 - lambda) x_i + lambda * weighted mean
  }
  const double volume = s.spacing * s.spacing * s.spacing;
  const Mat3d identity{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  if (neighbours < s.isolatedBelow) {
    const double a = s.support * s.isolatedScale;
    return makeKernel(center, identity, {a, a, a}, volume);
  }
  Mat3d cov{};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) cov[a][b] = m2[a][b] / wsum - mean[a] * mean[b];
  Vec3d sigma{};
  Mat3d rot{};
  symmetricEigen(cov, sigma, rot);
  const double full = kFullVariance * h2;
  // Yu & Turk: clamp the small axes to sigma_1 / k_r, scale by k_s = 1 / full. The upper clamp bounds
  // the support (and so the gather distance) for stretched kernels along thin streams.
  constexpr double kMaxAxis = 2.0;
  Vec3d axes{};
  for (int a = 0; a < 3; ++a)
    axes[a] = s.support * std::clamp(std::max(sigma[a], sigma[0] / s.maxStretch) / full, 0.25, kMaxAxis);
  return makeKernel(center, rot, axes, volume);
}

/// A kernel prepared for splatting: its ellipsoid's half-extent along each axis, sqrt((M^-1)_aa) (m),
/// widened so that every voxel where the float evaluation of q^2 is below 1 lies inside it.
std::array<float, 3> axisExtents(const AnisotropicKernel& k) {
  const double a = k.metric[0], b = k.metric[1], c = k.metric[2], d = k.metric[3], e = k.metric[4],
               f = k.metric[5];
  const double det = a * (d * f - e * e) - b * (b * f - c * e) + c * (b * e - c * d);
  const double inv[3] = {(d * f - e * e) / det, (a * f - c * c) / det, (a * d - b * b) / det};
  std::array<float, 3> ext{};
  for (int i = 0; i < 3; ++i) {
    // Never beyond the longest axis (the old box), never below zero for a degenerate metric.
    const double x = det > 0 && inv[i] > 0 ? std::sqrt(inv[i]) * 1.001 + 1e-6 : double(k.extent);
    ext[i] = float(std::min(x, double(k.extent)));
  }
  return ext;
}

/// A kernel in voxel units, ready to splat: centre, metric times voxel^2, weight, and the box of voxels
/// (inclusive) outside which q^2 is never below 1.
struct Splat {
  float cx, cy, cz;
  float mxx, mxy, mxz, myy, myz, mzz;
  float weight;
  std::array<int, 3> lo, hi;
};

Splat prepareSplat(const AnisotropicKernel& k, double voxel) {
  Splat s;
  s.cx = float(k.center[0] / voxel);
  s.cy = float(k.center[1] / voxel);
  s.cz = float(k.center[2] / voxel);
  const float v2 = float(voxel * voxel);
  s.mxx = k.metric[0] * v2, s.mxy = k.metric[1] * v2, s.mxz = k.metric[2] * v2;
  s.myy = k.metric[3] * v2, s.myz = k.metric[4] * v2, s.mzz = k.metric[5] * v2;
  s.weight = k.weight;
  const auto ext = axisExtents(k);
  const float c[3] = {s.cx, s.cy, s.cz};
  for (int i = 0; i < 3; ++i) {
    s.lo[i] = int(std::floor(c[i] - ext[i] / voxel));
    s.hi[i] = int(std::ceil(c[i] + ext[i] / voxel));
  }
  return s;
}

/// Accumulates the density of `k` into the 8^3 block whose first voxel is `origin`. Each row along z
/// visits only the voxels where the quadratic q^2(z) can be below 1 (its roots widened by one voxel,
/// then the same float test as for every voxel), so the sums are those of visiting the whole box.
/// Kernels binned by the 8^3 block holding their centre: their range in the splat order and the union
/// of their voxel boxes.
struct DensityBin {
  size_t begin, end;
  openvdb::CoordBBox box;  // voxels its kernels can reach
};
using DensityBins = std::unordered_map<uint64_t, DensityBin>;

inline __attribute__((always_inline)) void splat(const Splat& k, const openvdb::Coord& origin, float* acc) {
  const int x0 = std::max(origin.x(), k.lo[0]), x1 = std::min(origin.x() + 7, k.hi[0]);
  const int y0 = std::max(origin.y(), k.lo[1]), y1 = std::min(origin.y() + 7, k.hi[1]);
  const int z0 = std::max(origin.z(), k.lo[2]), z1 = std::min(origin.z() + 7, k.hi[2]);
  if (x0 > x1 || y0 > y1 || z0 > z1) return;
  const double inv2mzz = 1.0 / (2.0 * k.mzz);
  // The block's 8 z voxels as one row: dz per lane (integers plus a float: exactly float(z) - cz).
  const Float8 lane = {0, 1, 2, 3, 4, 5, 6, 7}, zero = {};
  const Float8 dz = (lane + float(origin.z())) - k.cz;
  for (int x = x0; x <= x1; ++x) {
    const float dx = float(x) - k.cx;
    for (int y = y0; y <= y1; ++y) {
      const float dy = float(y) - k.cy;
      const float base = k.mxx * dx * dx + 2 * k.mxy * dx * dy + k.myy * dy * dy;
      const float bx = 2 * (k.mxz * dx + k.myz * dy);
      // q2(z) = base + bx dz + mzz dz^2 < 1 between the roots, widened by a voxel against rounding.
      // The row's smallest q2 is 1 - disc / (4 mzz): skip the row when that is clearly above 1.
      const double disc = double(bx) * bx - 4.0 * k.mzz * (double(base) - 1.0);
      if (-disc * inv2mzz > 2e-3 * (1.0 + std::abs(double(base)))) continue;
      const double mid = k.cz - bx * inv2mzz, half = std::sqrt(std::max(disc, 0.0)) * inv2mzz;
      const int za = std::max(z0, int(std::floor(mid - half)) - 1),
                zb = std::min(z1, int(std::ceil(mid + half)) + 1);
      if (za > zb) continue;
      // All 8 voxels at once; those outside [za, zb] or with q2 >= 1 add nothing (as the scalar loop
      // over [za, zb] that skipped q2 >= 1: the same sums, bit for bit).
      const Float8 q2 = base + dz * (bx + k.mzz * dz), t = 1.f - q2;
      const auto take = (q2 < 1.f) & (lane >= float(za - origin.z())) & (lane <= float(zb - origin.z()));
      float* row = acc + ((x - origin.x()) << 6) + ((y - origin.y()) << 3);
      store8(row, load8(row) + (take ? k.weight * t * t * t : zero));
    }
  }
}

/// The summed density of the kernels binned within `reach` blocks of block `b`, into `acc` (cleared
/// first), gathered in a fixed order. Built for the baseline and for AVX2 (simd.h).
inline __attribute__((always_inline)) void densityOfBlock(const openvdb::Coord& b, int reach,
                                                          const DensityBins& bins,
                                                          const std::vector<Splat>& splats, float* acc) {
  const openvdb::Coord origin = b << 3;
  const openvdb::CoordBBox blockBox(origin, origin.offsetBy(7));
  std::fill(acc, acc + 512, 0.f);
  for (int dx = -reach; dx <= reach; ++dx)
    for (int dy = -reach; dy <= reach; ++dy)
      for (int dz = -reach; dz <= reach; ++dz) {
        auto it = bins.find(packKey(b.x() + dx, b.y() + dy, b.z() + dz));
        if (it == bins.end() || !it->second.box.hasOverlap(blockBox)) continue;
        for (size_t k = it->second.begin; k < it->second.end; ++k) splat(splats[k], origin, acc);
      }
}

void densityOfBlockBaseline(const openvdb::Coord& b, int reach, const DensityBins& bins,
                            const std::vector<Splat>& splats, float* acc) {
  densityOfBlock(b, reach, bins, splats, acc);
}

SPHFX_TARGET_AVX2 void densityOfBlockAvx2(const openvdb::Coord& b, int reach, const DensityBins& bins,
                                          const std::vector<Splat>& splats, float* acc) {
  densityOfBlock(b, reach, bins, splats, acc);
}

}  // namespace

std::vector<AnisotropicKernel> computeAnisotropicKernels(const std::vector<std::array<float, 3>>& positions,
                                                         const AnisotropicSettings& settings) {
  return computeAnisotropicKernels(positions, settings, SimdIsa::Auto);
}

std::vector<AnisotropicKernel> computeAnisotropicKernels(const std::vector<std::array<float, 3>>& positions,
                                                         const AnisotropicSettings& settings, SimdIsa isa) {
  if (!(settings.spacing > 0) || !(settings.support > 0))
    throw InputError("anisotropic kernels: spacing and support must be positive");
  std::vector<AnisotropicKernel> kernels(positions.size());
  if (positions.empty()) return kernels;
  const CellGrid cells(positions, settings.support);
  const auto sum = useAvx2(isa) ? sumMomentsAvx2 : sumMomentsBaseline;
  const float h = float(settings.support);
  // Cell by cell: the 27 cells' particles are gathered once for all the particles of a cell.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, cells.cells().size(), 16), [&](const auto& r) {
    Candidates candidates;
    LaneSums sums;
    for (size_t ci = r.begin(); ci != r.end(); ++ci) {
      const auto& cell = cells.cells()[ci];
      const auto& origin = positions[cells.order()[cell.begin]];
      candidates.clear();
      cells.forEachNear(cell.coord, [&](uint32_t j) {
        candidates.push(float(double(positions[j][0]) - origin[0]),
                        float(double(positions[j][1]) - origin[1]),
                        float(double(positions[j][2]) - origin[2]));
      });
      candidates.pad();
      for (uint32_t k = cell.begin; k < cell.end; ++k) {
        const uint32_t i = cells.order()[k];
        const auto& xi = positions[i];
        sum(candidates, float(double(xi[0]) - origin[0]), float(double(xi[1]) - origin[1]),
            float(double(xi[2]) - origin[2]), h, sums);
        kernels[i] = kernelFor(xi, sums, settings);
      }
    }
  });
  return kernels;
}

namespace {

constexpr float kIso = 0.5f;  // half the density of a full neighbourhood

/// iso - density on the 8^3 blocks that some kernel's box touches (all voxels active), background iso.
openvdb::FloatGrid::Ptr densityField(const std::vector<AnisotropicKernel>& kernels, double voxelSize,
                                     SimdIsa isa) {
  using LeafT = openvdb::FloatTree::LeafNodeType;
  // Kernels binned by the 8^3 block holding their centre, in a fixed order (block, then index), each
  // bin with the union of its kernels' voxel boxes.
  auto blockOf = [&](const std::array<float, 3>& c) {
    return openvdb::Coord(int(std::floor(c[0] / voxelSize + 0.5)), int(std::floor(c[1] / voxelSize + 0.5)),
                          int(std::floor(c[2] / voxelSize + 0.5))) >>
           3;
  };
  std::vector<std::pair<uint64_t, uint32_t>> keyed(kernels.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, kernels.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const auto b = blockOf(kernels[i].center);
      keyed[i] = {packKey(b.x(), b.y(), b.z()), uint32_t(i)};
    }
  });
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<Splat> splats(kernels.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, kernels.size(), 4096), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i)
      splats[i] = prepareSplat(kernels[keyed[i].second], voxelSize);
  });
  DensityBins bins;
  std::vector<const DensityBin*> binList;
  float maxExtent = 0;
  for (size_t i = 0; i < keyed.size(); ++i) {
    const Splat& k = splats[i];
    const openvdb::CoordBBox box(openvdb::Coord(k.lo[0], k.lo[1], k.lo[2]),
                                 openvdb::Coord(k.hi[0], k.hi[1], k.hi[2]));
    if (i == 0 || keyed[i].first != keyed[i - 1].first) {
      binList.push_back(&(bins[keyed[i].first] = {i, i, box}));
    }
    DensityBin& bin = bins[keyed[i].first];
    bin.end = i + 1;
    bin.box.expand(box);
    maxExtent = std::max(maxExtent, kernels[keyed[i].second].extent);
  }
  // Bins whose kernels can reach a block: within `reach` blocks of it.
  const int reach = int(std::ceil((maxExtent / voxelSize + 1) / 8.0));
  // The blocks some kernel's box touches.
  std::vector<openvdb::Coord> blocks;
  for (const DensityBin* bin : binList) {
    const openvdb::Coord lo = bin->box.min() >> 3, hi = bin->box.max() >> 3;
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z) blocks.emplace_back(x, y, z);
  }
  tbb::parallel_sort(blocks.begin(), blocks.end());
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());

  std::vector<std::unique_ptr<LeafT>> leaves(blocks.size());
  const auto density = useAvx2(isa) ? densityOfBlockAvx2 : densityOfBlockBaseline;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks.size(), 4), [&](const auto& r) {
    alignas(32) std::array<float, 512> acc;
    for (size_t bi = r.begin(); bi != r.end(); ++bi) {
      const openvdb::Coord b = blocks[bi], origin = b << 3;
      density(b, reach, bins, splats, acc.data());
      if (*std::max_element(acc.begin(), acc.end()) == 0.f) continue;
      auto leaf = std::make_unique<LeafT>(origin, kIso, true);
      for (openvdb::Index n = 0; n < LeafT::SIZE; ++n) leaf->setValueOnly(n, kIso - acc[n]);
      leaves[bi] = std::move(leaf);
    }
  });
  // The density field, negated so that inside is negative, with "empty" (outside) as background.
  auto field = openvdb::FloatGrid::create(kIso);
  field->setTransform(openvdb::math::Transform::createLinearTransform(voxelSize));
  for (auto& leaf : leaves)
    if (leaf) field->tree().addLeaf(leaf.release());
  return field;
}

}  // namespace

openvdb::FloatGrid::Ptr rasterizeAnisotropic(const std::vector<AnisotropicKernel>& kernels, double voxelSize,
                                             double halfWidth,
                                             const std::function<void(const char*)>& stage) {
  return rasterizeAnisotropic(kernels, voxelSize, halfWidth, stage, SimdIsa::Auto);
}

openvdb::FloatGrid::Ptr rasterizeAnisotropic(const std::vector<AnisotropicKernel>& kernels, double voxelSize,
                                             double halfWidth, const std::function<void(const char*)>& stage,
                                             SimdIsa isa) {
  auto lap = [&](const char* name) {
    if (stage) stage(name);
  };
  using LeafT = openvdb::FloatTree::LeafNodeType;
  if (kernels.empty()) return openvdb::createLevelSet<openvdb::FloatGrid>(voxelSize, halfWidth);

  const auto field = densityField(kernels, voxelSize, isa);
  lap("density");
  // Only the voxels within halfWidth + 1 (L-infinity) of a crossing of the 1/2 density (a voxel whose
  // face neighbour is on the other side) are needed; voxels of the band beyond the evaluated blocks
  // keep the background (zero density, outside).
  auto band = openvdb::tools::extractIsosurfaceMask(field->tree(), 0.f);
  openvdb::tools::dilateActiveValues(*band, int(std::ceil(halfWidth)) + 1,
                                     openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::IGNORE_TILES);
  // (Not Tree::topologyIntersection: it replaces the interior's leaves by background, i.e. outside.)
  openvdb::tree::LeafManager<openvdb::FloatTree>(field->tree()).foreach ([&](LeafT& leaf, size_t) {
    const auto* keep = band->probeConstLeaf(leaf.origin());
    leaf.setValueMask(keep ? keep->getValueMask() : LeafT::NodeMaskType());
  });
  field->tree().topologyUnion(*band);
  openvdb::tools::pruneLevelSet(field->tree());  // the interior's inactive leaves to inside tiles
  lap("band");
  // Signed distances in the band: first-order distances to the crossing at the voxels next to it (linear
  // interpolation of the density along each axis), then the Eikonal equation layer by layer.
  openvdb::FloatGrid::Ptr sdf = bandDistances(*field, halfWidth + 1);
  lap("sweep");
  // The narrow band: inactive values +-halfWidth voxels, active voxels beyond it switched off, pruned.
  openvdb::tools::changeLevelSetBackground(sdf->tree(), float(halfWidth * voxelSize));
  sdf->setGridClass(openvdb::GRID_LEVEL_SET);
  openvdb::tools::LevelSetTracker<openvdb::FloatGrid>(*sdf).prune();
  lap("trim");
  return sdf;
}

}  // namespace sphfx::surfacing
