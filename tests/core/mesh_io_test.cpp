// PLY round trip, and an independent check of the bytes: the header is parsed by hand here and the
// binary body decoded with memcpy, not with our reader.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sphfx/core/error.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/mesh_io.h"

using namespace sphfx;
namespace fs = std::filesystem;

namespace {
TriangleMesh tetrahedron() {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (const auto& p : m.positions) {
    const float l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    m.normals.push_back(l > 0 ? std::array<float, 3>{p[0] / l, p[1] / l, p[2] / l}
                              : std::array<float, 3>{0, -1, 0});
  }
  return m;
}
}  // namespace

TEST(MeshIo, BinaryRoundTripAndLayout) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_mesh_test";
  const std::string path = meshPath(dir.string(), 7);
  EXPECT_EQ(fs::path(path).filename(), "mesh.0007.ply");
  const TriangleMesh m = tetrahedron();
  writePly(path, m);

  const std::string bytes = readTextFile(path);
  const auto end = bytes.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  EXPECT_NE(bytes.find("element vertex 4\n"), std::string::npos);
  EXPECT_NE(bytes.find("element face 4\n"), std::string::npos);
  const size_t body = end + 11;
  ASSERT_EQ(bytes.size() - body, 4 * 24 + 4 * 13u);
  float x1;
  std::memcpy(&x1, bytes.data() + body + 24, 4);  // vertex 1, x
  EXPECT_EQ(x1, 1.0f);
  int32_t lastIndex;
  std::memcpy(&lastIndex, bytes.data() + body + 96 + 3 * 13 + 1 + 8, 4);  // face 3, third index
  EXPECT_EQ(lastIndex, 3);

  const TriangleMesh r = readPly(path);
  EXPECT_EQ(r.positions, m.positions);
  EXPECT_EQ(r.normals, m.normals);
  EXPECT_EQ(r.triangles, m.triangles);
  fs::remove_all(dir);
}

TEST(MeshIo, AsciiQuadsAreSplitAndNormalsComputed) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_mesh_test2";
  fs::create_directories(dir);
  const std::string path = (dir / "quad.ply").string();
  std::ofstream(path)
      << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
  const TriangleMesh r = readPly(path);
  ASSERT_EQ(r.triangles.size(), 2u);
  for (const auto& n : r.normals) EXPECT_FLOAT_EQ(n[2], 1.0f);
  fs::remove_all(dir);
}

TEST(MeshIo, MalformedInputIsAnInputError) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_mesh_test3";
  fs::create_directories(dir);
  std::ofstream((dir / "a.ply").string()) << "not a ply\n";
  EXPECT_THROW(readPly((dir / "a.ply").string()), InputError);
  std::ofstream((dir / "b.ply").string()) << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                             "element face 1\nproperty list uchar int vertex_indices\n"
                                             "end_header\n0\n3 0 1 2\n";
  EXPECT_THROW(readPly((dir / "b.ply").string()), InputError);
  TriangleMesh bad = tetrahedron();
  bad.triangles.push_back({0, 1, 9});
  EXPECT_THROW(writePly((dir / "c.ply").string(), bad), InputError);
  fs::remove_all(dir);
}
