#pragma once
/// @file anisotropic.h
/// @brief Yu & Turk (2013) anisotropic kernels: a weighted PCA of each particle's neighbourhood gives an
/// ellipsoidal kernel (flat at flat surfaces, long along thin streams, a small sphere for an isolated
/// particle), centred on a Laplacian-smoothed position. The kernels' summed density is rasterized into a
/// narrow-band level set. CPU, TBB, deterministic for any thread count.

#include <openvdb/openvdb.h>

#include <array>
#include <functional>
#include <vector>

namespace sphfx::surfacing {

/// One particle's kernel: W(x) = weight * P(|M^(1/2) (x - center)|^2), P(q2) = (1 - q2)^3 for q2 < 1.
struct AnisotropicKernel {
  std::array<float, 3> center{};  ///< smoothed centre (m)
  std::array<float, 6> metric{};  ///< symmetric M = G^T G: xx, xy, xz, yy, yz, zz (1/m^2)
  float weight = 0;               ///< particle volume times the kernel's normalisation
  float extent = 0;               ///< support half-extent along the longest axis (m)
};

struct AnisotropicSettings {
  double spacing = 0;          ///< particle spacing s (m): particle volume s^3
  double support = 0;          ///< kernel support radius of a full, isotropic neighbourhood (m)
  double lambda = 0.9;         ///< Laplacian smoothing of the centres (Yu & Turk: 0.9..1)
  double maxStretch = 4;       ///< k_r: largest ratio between the axes
  int isolatedBelow = 6;       ///< N_eps: fewer neighbours than this gives a small isotropic kernel
  double isolatedScale = 0.5;  ///< k_n: support of such a kernel, relative to `support`
};

/// Kernels of `positions` (one per particle, same order). Deterministic.
/// @throws InputError if spacing or support is not positive.
std::vector<AnisotropicKernel> computeAnisotropicKernels(const std::vector<std::array<float, 3>>& positions,
                                                         const AnisotropicSettings& settings);

/// The narrow-band level set (half width `halfWidth` voxels) of the iso-surface where the kernels'
/// summed density is 1/2 (inside: denser), sampled on voxels of `voxelSize`. Deterministic.
/// `stage`, if set, is called with each step's name when that step ends (for timings).
openvdb::FloatGrid::Ptr rasterizeAnisotropic(const std::vector<AnisotropicKernel>& kernels, double voxelSize,
                                             double halfWidth,
                                             const std::function<void(const char*)>& stage = {});

}  // namespace sphfx::surfacing
