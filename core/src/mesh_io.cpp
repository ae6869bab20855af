#include "sphfx/core/mesh_io.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"

namespace fs = std::filesystem;
static_assert(std::endian::native == std::endian::little, "PLY I/O assumes a little-endian host");

namespace sphfx {

std::string meshPath(const std::string& shotDir, int frame) {
  return framePath((fs::path(shotDir) / "mesh").string(), "mesh", frame, "ply");
}
std::string surfacePath(const std::string& shotDir, int frame) {
  return framePath((fs::path(shotDir) / "surface").string(), "surface", frame, "vdb");
}
std::string renderPath(const std::string& shotDir, const std::string& source, int frame,
                       const std::string& ext) {
  return framePath((fs::path(shotDir) / "render").string(), source, frame, ext);
}

void writePly(const std::string& path, const TriangleMesh& mesh) {
  if (mesh.normals.size() != mesh.positions.size())
    throw InputError(path + ": mesh has " + std::to_string(mesh.normals.size()) + " normals for " +
                     std::to_string(mesh.positions.size()) + " vertices");
  for (const auto& t : mesh.triangles)
    for (uint32_t i : t)
      if (i >= mesh.positions.size()) throw InputError(path + ": triangle index past the vertex count");
  writeFileAtomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\ncomment sphfx mesh\n"
        << "element vertex " << mesh.positions.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\n"
        << "property float nx\nproperty float ny\nproperty float nz\n"
        << "element face " << mesh.triangles.size() << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    std::vector<char> buffer;
    buffer.reserve(mesh.positions.size() * 24 + mesh.triangles.size() * 13);
    auto put = [&](const void* p, size_t n) {
      buffer.insert(buffer.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n);
    };
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      put(mesh.positions[i].data(), 12);
      put(mesh.normals[i].data(), 12);
    }
    for (const auto& t : mesh.triangles) {
      const uint8_t three = 3;
      put(&three, 1);
      const int32_t idx[3] = {int32_t(t[0]), int32_t(t[1]), int32_t(t[2])};
      put(idx, 12);
    }
    out.write(buffer.data(), std::streamsize(buffer.size()));
    out.close();
    if (!out) throw IoError(path + ": cannot write");
  });
}

namespace {

struct PlyProperty {
  std::string name, type, countType;  // countType set for lists
};
struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
};

size_t typeSize(const std::string& t, const std::string& path) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  throw InputError(path + ": unknown PLY property type \"" + t + "\"");
}

double readBinary(std::istream& in, const std::string& t, const std::string& path) {
  unsigned char b[8] = {};
  const size_t n = typeSize(t, path);
  if (!in.read(reinterpret_cast<char*>(b), std::streamsize(n)))
    throw InputError(path + ": PLY data ends early");
  auto as = [&](auto v) {
    std::memcpy(&v, b, sizeof(v));
    return double(v);
  };
  if (t == "char" || t == "int8") return as(int8_t{});
  if (t == "uchar" || t == "uint8") return as(uint8_t{});
  if (t == "short" || t == "int16") return as(int16_t{});
  if (t == "ushort" || t == "uint16") return as(uint16_t{});
  if (t == "int" || t == "int32") return as(int32_t{});
  if (t == "uint" || t == "uint32") return as(uint32_t{});
  if (t == "float" || t == "float32") return as(float{});
  return as(double{});
}

}  // namespace

void computeVertexNormals(TriangleMesh& m) {
  m.normals.assign(m.positions.size(), {0, 0, 0});
  for (const auto& t : m.triangles) {
    const auto &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
    const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
    for (uint32_t i : t)
      for (int k = 0; k < 3; ++k) m.normals[i][k] += n[k];
  }
  for (auto& n : m.normals) {
    const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0)
      for (float& c : n) c /= len;
  }
}

TriangleMesh readPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open");
  std::string line, format;
  std::getline(in, line);
  if (line != "ply" && line != "ply\r") throw InputError(path + ": not a PLY file (no \"ply\" magic)");
  std::vector<PlyElement> elements;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "end_header") break;
    if (key == "format") words >> format;
    if (key == "element") {
      PlyElement e;
      words >> e.name >> e.count;
      elements.push_back(e);
    }
    if (key == "property") {
      if (elements.empty()) throw InputError(path + ": PLY property before any element");
      PlyProperty p;
      words >> p.type;
      if (p.type == "list") words >> p.countType >> p.type;
      words >> p.name;
      elements.back().properties.push_back(p);
    }
  }
  const bool ascii = format == "ascii";
  if (!ascii && format != "binary_little_endian")
    throw InputError(path + ": expected PLY format ascii or binary_little_endian, got \"" + format + "\"");

  TriangleMesh mesh;
  bool hasNormals = false;
  auto value = [&](const std::string& type) {
    if (!ascii) return readBinary(in, type, path);
    double v;
    if (!(in >> v)) throw InputError(path + ": PLY data ends early");
    return v;
  };
  for (const PlyElement& e : elements) {
    for (size_t i = 0; i < e.count; ++i) {
      std::array<float, 3> p{}, n{};
      for (const PlyProperty& prop : e.properties) {
        if (!prop.countType.empty()) {
          const auto count = size_t(value(prop.countType));
          std::vector<uint32_t> idx(count);
          for (auto& k : idx) k = uint32_t(value(prop.type));
          if (e.name == "face" && prop.name.rfind("vertex_ind", 0) == 0)
            for (size_t k = 2; k < count; ++k) mesh.triangles.push_back({idx[0], idx[k - 1], idx[k]});  // fan
          continue;
        }
        const double v = value(prop.type);
        const std::string& nm = prop.name;
        if (nm == "x" || nm == "y" || nm == "z") p[size_t(nm[0] - 'x')] = float(v);
        if (nm == "nx" || nm == "ny" || nm == "nz") n[size_t(nm[1] - 'x')] = float(v), hasNormals = true;
      }
      if (e.name == "vertex") {
        mesh.positions.push_back(p);
        mesh.normals.push_back(n);
      }
    }
  }
  for (const auto& t : mesh.triangles)
    for (uint32_t i : t)
      if (i >= mesh.positions.size())
        throw InputError(
            fmt::format("{}: face index {} is past the {} vertices", path, i, mesh.positions.size()));
  if (!hasNormals) computeVertexNormals(mesh);
  return mesh;
}

}  // namespace sphfx
