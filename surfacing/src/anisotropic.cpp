// Yu & Turk (2013), "Reconstructing surfaces of particle-based fluids using anisotropic kernels".
//
// Determinism: every per-particle and per-block result is computed by one task from inputs visited in a
// fixed order (particles sorted by cell then index; kernels gathered block by block in a fixed order), so
// floating-point sums do not depend on how TBB splits the work.
#include "sphfx/surfacing/anisotropic.h"

#include <openvdb/tools/LevelSetRebuild.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

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
      if (i == 0 || keyed[i].first != keyed[i - 1].first)
        ranges_[keyed[i].first] = {uint32_t(i), uint32_t(i)};
      ranges_[keyed[i].first].second = uint32_t(i + 1);
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

  /// Calls f(j) for every particle j in the 27 cells around `x`, in a fixed order.
  template <class F>
  void forEachNear(const std::array<float, 3>& x, F&& f) const {
    const auto c = coord(x);
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

AnisotropicKernel kernelFor(const std::vector<std::array<float, 3>>& p, const CellGrid& cells, size_t i,
                            const AnisotropicSettings& s) {
  const double h = s.support, h2 = h * h;
  const auto& xi = p[i];
  // One pass in coordinates relative to x_i (doubles): weight sum, first and second moments.
  double wsum = 0;
  Vec3d m1{0, 0, 0};
  Mat3d m2{};
  int neighbours = 0;
  cells.forEachNear(xi, [&](uint32_t j) {
    const double d[3] = {double(p[j][0]) - xi[0], double(p[j][1]) - xi[1], double(p[j][2]) - xi[2]};
    const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (r2 >= h2) return;
    const double r = std::sqrt(r2) / h;
    const double w = 1 - r * r * r;
    wsum += w;
    neighbours += j != i;
    for (int a = 0; a < 3; ++a) {
      m1[a] += w * d[a];
      for (int b = 0; b < 3; ++b) m2[a][b] += w * d[a] * d[b];
    }
  });
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

/// Accumulates the density of `k` into the 8^3 block whose first voxel is `origin`.
void splat(const AnisotropicKernel& k, double voxel, const openvdb::Coord& origin, float* acc) {
  const double e = k.extent / voxel;
  const double cx = k.center[0] / voxel, cy = k.center[1] / voxel, cz = k.center[2] / voxel;
  const int x0 = std::max(origin.x(), int(std::floor(cx - e))),
            x1 = std::min(origin.x() + 7, int(std::ceil(cx + e)));
  const int y0 = std::max(origin.y(), int(std::floor(cy - e))),
            y1 = std::min(origin.y() + 7, int(std::ceil(cy + e)));
  const int z0 = std::max(origin.z(), int(std::floor(cz - e))),
            z1 = std::min(origin.z() + 7, int(std::ceil(cz + e)));
  if (x0 > x1 || y0 > y1 || z0 > z1) return;
  const float v2 = float(voxel * voxel);
  const float mxx = k.metric[0] * v2, mxy = k.metric[1] * v2, mxz = k.metric[2] * v2;
  const float myy = k.metric[3] * v2, myz = k.metric[4] * v2, mzz = k.metric[5] * v2;
  for (int x = x0; x <= x1; ++x) {
    const float dx = float(x - cx);
    for (int y = y0; y <= y1; ++y) {
      const float dy = float(y - cy);
      const float base = mxx * dx * dx + 2 * mxy * dx * dy + myy * dy * dy;
      const float bx = 2 * (mxz * dx + myz * dy);
      float* row = acc + ((x - origin.x()) << 6) + ((y - origin.y()) << 3) - origin.z();
      for (int z = z0; z <= z1; ++z) {
        const float dz = float(z - cz);
        const float q2 = base + dz * (bx + mzz * dz);
        if (q2 >= 1.f) continue;
        const float t = 1.f - q2;
        row[z] += k.weight * t * t * t;
      }
    }
  }
}

}  // namespace

std::vector<AnisotropicKernel> computeAnisotropicKernels(const std::vector<std::array<float, 3>>& positions,
                                                         const AnisotropicSettings& settings) {
  if (!(settings.spacing > 0) || !(settings.support > 0))
    throw InputError("anisotropic kernels: spacing and support must be positive");
  std::vector<AnisotropicKernel> kernels(positions.size());
  if (positions.empty()) return kernels;
  const CellGrid cells(positions, settings.support);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, positions.size(), 1024), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) kernels[i] = kernelFor(positions, cells, i, settings);
  });
  return kernels;
}

openvdb::FloatGrid::Ptr rasterizeAnisotropic(const std::vector<AnisotropicKernel>& kernels, double voxelSize,
                                             double halfWidth) {
  using LeafT = openvdb::FloatTree::LeafNodeType;
  constexpr float kIso = 0.5f;  // half the density of a full neighbourhood
  auto transform = openvdb::math::Transform::createLinearTransform(voxelSize);
  if (kernels.empty()) return openvdb::createLevelSet<openvdb::FloatGrid>(voxelSize, halfWidth);

  // Kernels binned by the 8^3 block holding their centre, in a fixed order.
  auto blockOf = [&](const std::array<float, 3>& c) {
    return openvdb::Coord(int(std::floor(c[0] / voxelSize + 0.5)), int(std::floor(c[1] / voxelSize + 0.5)),
                          int(std::floor(c[2] / voxelSize + 0.5))) >>
           3;
  };
  std::vector<std::pair<uint64_t, uint32_t>> keyed(kernels.size());
  float maxExtent = 0;
  for (size_t i = 0; i < kernels.size(); ++i) {
    const auto b = blockOf(kernels[i].center);
    keyed[i] = {packKey(b.x(), b.y(), b.z()), uint32_t(i)};
    maxExtent = std::max(maxExtent, kernels[i].extent);
  }
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::unordered_map<uint64_t, std::pair<size_t, size_t>> bins;
  for (size_t i = 0; i < keyed.size(); ++i) {
    if (i == 0 || keyed[i].first != keyed[i - 1].first) bins[keyed[i].first] = {i, i};
    bins[keyed[i].first].second = i + 1;
  }
  // Blocks a kernel can reach: its own block dilated by `reach` blocks.
  const int reach = int(std::ceil((maxExtent / voxelSize + 1) / 8.0));
  std::vector<openvdb::Coord> blocks;
  for (const auto& [k, range] : bins) {
    const auto b = blockOf(kernels[keyed[range.first].second].center);
    for (int dx = -reach; dx <= reach; ++dx)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dz = -reach; dz <= reach; ++dz) blocks.push_back(b.offsetBy(dx, dy, dz));
  }
  std::sort(blocks.begin(), blocks.end());
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());

  std::vector<std::unique_ptr<LeafT>> leaves(blocks.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks.size(), 4), [&](const auto& r) {
    std::array<float, 512> acc;
    for (size_t bi = r.begin(); bi != r.end(); ++bi) {
      const openvdb::Coord b = blocks[bi], origin = b << 3;
      acc.fill(0.f);
      for (int dx = -reach; dx <= reach; ++dx)
        for (int dy = -reach; dy <= reach; ++dy)
          for (int dz = -reach; dz <= reach; ++dz) {
            auto it = bins.find(packKey(b.x() + dx, b.y() + dy, b.z() + dz));
            if (it == bins.end()) continue;
            for (size_t k = it->second.first; k < it->second.second; ++k)
              splat(kernels[keyed[k].second], voxelSize, origin, acc.data());
          }
      if (*std::max_element(acc.begin(), acc.end()) == 0.f) continue;
      auto leaf = std::make_unique<LeafT>(origin, kIso, true);
      for (openvdb::Index n = 0; n < LeafT::SIZE; ++n) leaf->setValueOnly(n, kIso - acc[n]);
      leaves[bi] = std::move(leaf);
    }
  });
  // The density field, negated so that inside is negative, with "empty" (outside) as background.
  auto field = openvdb::FloatGrid::create(kIso);
  field->setTransform(transform);
  for (auto& leaf : leaves)
    if (leaf) field->tree().addLeaf(leaf.release());
  auto sdf =
      openvdb::tools::levelSetRebuild(*field, 0.f, float(halfWidth), float(halfWidth), transform.get());
  sdf->setGridClass(openvdb::GRID_LEVEL_SET);
  return sdf;
}

}  // namespace sphfx::surfacing
