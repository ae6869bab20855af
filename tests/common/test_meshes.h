#pragma once
// Collider geometry files for tests, written independently of sphfx's readers: an axis-aligned box as
// OBJ (quads), a UV sphere as binary STL, a single quad (an open surface) as ASCII STL.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "scratch_dir.h"

namespace sphfx::test {

using V3 = std::array<double, 3>;

/// An empty folder NAME in the process's scratch folder (scratch_dir.h) for a test's files.
inline std::filesystem::path freshTestDir(const std::string& name) {
  const std::filesystem::path d = scratchPath(name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

/// Box [lo, hi] as OBJ: 8 vertices, 6 outward-wound quads.
inline void writeBoxObj(const std::string& path, const V3& lo, const V3& hi) {
  std::ofstream out(path);
  for (int k = 0; k < 8; ++k)
    out << "v " << (k & 1 ? hi[0] : lo[0]) << ' ' << (k & 2 ? hi[1] : lo[1]) << ' ' << (k & 4 ? hi[2] : lo[2])
        << '\n';
  // Vertex k has bit 0 = x, bit 1 = y, bit 2 = z (1-based in the file).
  out << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
}

/// UV sphere of `stacks` x `slices` as binary STL (unit normals left zero, as many exporters do).
inline void writeSphereStl(const std::string& path, const V3& c, double r, int stacks, int slices) {
  std::vector<std::array<V3, 3>> tris;
  auto at = [&](int i, int j) {
    const double th = std::numbers::pi * i / stacks, ph = 2 * std::numbers::pi * (j % slices) / slices;
    return V3{c[0] + r * std::sin(th) * std::cos(ph), c[1] + r * std::cos(th),
              c[2] + r * std::sin(th) * std::sin(ph)};
  };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const V3 a = at(i, j), b = at(i + 1, j), d = at(i, j + 1), e = at(i + 1, j + 1);
      if (i > 0) tris.push_back({a, d, b});
      if (i + 1 < stacks) tris.push_back({d, e, b});
    }
  std::ofstream out(path, std::ios::binary);
  char header[80] = "solid written by a test as binary STL";
  out.write(header, 80);
  const uint32_t n = uint32_t(tris.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : tris) {
    float rec[12] = {};
    for (int v = 0; v < 3; ++v)
      for (int a = 0; a < 3; ++a) rec[3 + 3 * v + a] = float(t[v][a]);
    out.write(reinterpret_cast<const char*>(rec), 48);
    const uint16_t attr = 0;
    out.write(reinterpret_cast<const char*>(&attr), 2);
  }
}

/// The horizontal quad [x0, x1] x {y} x [z0, z1] as ASCII STL: an open surface (4 open edges).
inline void writeQuadStl(const std::string& path, double x0, double x1, double y, double z0, double z1) {
  std::ofstream out(path);
  auto facet = [&](V3 a, V3 b, V3 c) {
    out << "facet normal 0 1 0\n outer loop\n";
    for (const V3& p : {a, b, c}) out << "  vertex " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    out << " endloop\nendfacet\n";
  };
  out << "solid quad\n";
  facet({x0, y, z0}, {x0, y, z1}, {x1, y, z1});
  facet({x0, y, z0}, {x1, y, z1}, {x1, y, z0});
  out << "endsolid quad\n";
}

}  // namespace sphfx::test
