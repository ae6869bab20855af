#pragma once
// Shared helpers of the surfacing tests: lattices, mesh measures against analytic references, temp shots.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "sphfx/core/mesh_io.h"
#include "sphfx/core/particle_cache.h"

namespace sphfx::test {

using Points = std::vector<std::array<float, 3>>;

/// Cell-centred cubic lattice of spacing s inside the sphere of radius r at the origin: each particle
/// stands for one s^3 cell, so the particles' volume is about 4/3 pi r^3.
inline Points sphereLattice(double r, double s) {
  Points p;
  const int n = int(std::ceil(r / s)) + 1;
  for (int i = -n; i < n; ++i)
    for (int j = -n; j < n; ++j)
      for (int k = -n; k < n; ++k) {
        const double x = (i + 0.5) * s, y = (j + 0.5) * s, z = (k + 0.5) * s;
        if (x * x + y * y + z * z < r * r) p.push_back({float(x), float(y), float(z)});
      }
  return p;
}

/// A box [0, nx s] x [0, ny s] x [0, nz s] of cell-centred particles, jittered by up to `jitter` * s
/// (fixed seed), like a pool at rest after a simulation.
inline Points poolLattice(int nx, int ny, int nz, double s, double jitter) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-jitter * s, jitter * s);
  Points p;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k)
        p.push_back(
            {float((i + 0.5) * s + u(rng)), float((j + 0.5) * s + u(rng)), float((k + 0.5) * s + u(rng))});
  return p;
}

struct MeshMeasure {
  double volume = 0, area = 0;
  size_t badEdges = 0;  ///< edges not shared by exactly two triangles
};

/// Volume by the divergence theorem (sum of signed tetrahedra to the origin), area, and edge use counts.
inline MeshMeasure measure(const TriangleMesh& m) {
  MeshMeasure r;
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const auto& t : m.triangles) {
    const auto &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                 w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    r.volume += (a[0] * n[0] + a[1] * n[1] + a[2] * n[2]) / 6;
    r.area += std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 2;
    for (int e = 0; e < 3; ++e) {
      const uint32_t i = t[e], j = t[(e + 1) % 3];
      ++edges[{std::min(i, j), std::max(i, j)}];
    }
  }
  for (const auto& [e, count] : edges) r.badEdges += count != 2;
  return r;
}

/// A fresh temporary directory, removed by the destructor.
class TempDir {
 public:
  explicit TempDir(const std::string& name) {
    path_ =
        std::filesystem::temp_directory_path() / ("sphfx_surf_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  std::string str() const { return path_.string(); }
  std::string operator/(const std::string& s) const { return (path_ / s).string(); }

 private:
  std::filesystem::path path_;
};

/// Writes `p` as cache frame `frame` of the shot at `shot`.
inline void writeFrame(const std::string& shot, int frame, const Points& p, double spacing) {
  ParticleFrame f;
  f.frame = frame;
  f.time = frame / 24.0;
  f.particleSpacing = spacing;
  f.position = p;
  f.velocity.assign(p.size(), {0, 0, 0});
  writeParticleCache(particleCachePath(shot, frame), f);
}

}  // namespace sphfx::test
