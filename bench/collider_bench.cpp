// Mesh colliders: (1) the signed distance field build for a ~1M-triangle mesh (a UV sphere written as a
// binary STL): reading, meshToSignedDistanceField plus the dense copy, and reading it back from the shot's
// cache; (2) the cost of a mesh collider against the analytic one on the same scene: a dam break into a box
// obstacle, the box given analytically and as an OBJ file, runs alternated.
//
//   collider_bench [--triangles N] [--spacing S] [--frames F] [--rounds R]
//
// --spacing is the fluid spacing the field is built for (voxel = spacing / 2; default 0.01 m for the
// sphere of radius 0.5 m); --frames and --rounds size part (2) (default 10 frames at 30 fps, 3 rounds).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "simulator.h"
#include "sphfx/core/collider_geometry.h"
#include "sphfx/core/log.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gl_context.h"

namespace {

using namespace sphfx;
namespace fs = std::filesystem;

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A UV sphere of about `triangles` triangles as binary STL.
void writeSphereStl(const std::string& path, double r, size_t triangles) {
  const int stacks = std::max(4, int(std::sqrt(double(triangles) / 4))), slices = 2 * stacks;
  std::ofstream out(path, std::ios::binary);
  char header[80] = "collider_bench sphere";
  out.write(header, 80);
  const uint32_t n = uint32_t(2 * slices * (stacks - 1));
  out.write(reinterpret_cast<const char*>(&n), 4);
  auto at = [&](int i, int j) {
    const double th = std::numbers::pi * i / stacks, ph = 2 * std::numbers::pi * (j % slices) / slices;
    return std::array<float, 3>{float(r * std::sin(th) * std::cos(ph)), float(r * std::cos(th)),
                                float(r * std::sin(th) * std::sin(ph))};
  };
  auto tri = [&](std::array<float, 3> a, std::array<float, 3> b, std::array<float, 3> c) {
    float rec[12] = {};
    for (int k = 0; k < 3; ++k) rec[3 + k] = a[k], rec[6 + k] = b[k], rec[9 + k] = c[k];
    out.write(reinterpret_cast<const char*>(rec), 48);
    const uint16_t attr = 0;
    out.write(reinterpret_cast<const char*>(&attr), 2);
  };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      if (i > 0) tri(at(i, j), at(i, j + 1), at(i + 1, j));
      if (i + 1 < stacks) tri(at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
    }
}

void fieldBuild(size_t triangles, double spacing) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_collider_bench";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string file = (dir / "sphere.stl").string();
  writeSphereStl(file, 0.5, triangles);
  Collider c;
  c.shape = Shape::Mesh;
  c.file = file;
  auto t0 = std::chrono::steady_clock::now();
  const TriangleMesh m = readColliderMesh(file);
  const double read = seconds(t0);
  const FieldSpec spec{0.5 * spacing, 0.04 * 4 / 2 + spacing, spacing};  // h = 2 s at this spacing
  t0 = std::chrono::steady_clock::now();
  const std::string cache = (dir / "shot/colliders/collider.0.vdb").string();
  bool rebuilt = false;
  const ColliderField f = buildColliderField(c, 0, spec, cache, &rebuilt);
  const double build = seconds(t0);
  t0 = std::chrono::steady_clock::now();
  buildColliderField(c, 0, spec, cache, &rebuilt);
  const double cached = seconds(t0);
  std::printf(
      "field: %zu triangles (%.1f MB STL), read %.2f s; SDF at voxel %.4f m: %d x %d x %d = %.1fM voxels, "
      "built (read + meshToSignedDistanceField + dense copy + cache write) in %.2f s; from the shot's cache "
      "in %.2f s (%s)\n",
      m.triangles.size(), double(fs::file_size(file)) / 1e6, read, spec.voxel, f.dims[0], f.dims[1],
      f.dims[2], double(f.voxelCount()) / 1e6, build, cached, rebuilt ? "rebuilt!" : "not rebuilt");
  fs::remove_all(dir);
}

double runSeconds(const Scene& scene) {
  sim::Simulator sim(scene);
  const auto t0 = std::chrono::steady_clock::now();
  while (sim.frame() < scene.time.endFrame) sim.advance();
  return seconds(t0);
}

void meshAgainstAnalytic(int frames, int rounds) {
  const fs::path dir = fs::temp_directory_path() / "sphfx_collider_bench_box";
  fs::create_directories(dir);
  const std::string obj = (dir / "box.obj").string();
  {
    std::ofstream out(obj);
    const double lo[3] = {0.6, 0, 0}, hi[3] = {0.7, 0.1, 0.1};
    for (int k = 0; k < 8; ++k)
      out << "v " << (k & 1 ? hi[0] : lo[0]) << ' ' << (k & 2 ? hi[1] : lo[1]) << ' '
          << (k & 4 ? hi[2] : lo[2]) << '\n';
    out << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  }
  const std::string base = std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json";
  const std::vector<std::string> common = {"time.end_frame=" + std::to_string(frames)};
  std::vector<std::string> analyticSets = common, meshSets = common;
  analyticSets.push_back(R"(colliders=[{"shape": "box", "min": [0.6,0,0], "max": [0.7,0.1,0.1]}])");
  meshSets.push_back(R"(colliders=[{"shape": "mesh", "file": ")" + obj + "\"}]");
  const Scene analytic = loadScene(base, analyticSets), mesh = loadScene(base, meshSets);
  std::vector<double> ratios;
  for (int r = 0; r < rounds; ++r) {
    const double a = runSeconds(analytic), m = runSeconds(mesh);
    ratios.push_back(m / a);
    std::printf("round %d: analytic box %.2f s, mesh box %.2f s, mesh / analytic %.3f\n", r + 1, a, m, m / a);
  }
  std::sort(ratios.begin(), ratios.end());
  std::printf("dam break into a box (%zu particles, %d frames): median mesh / analytic time %.3f\n",
              countInitialParticles(analytic), frames, ratios[ratios.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  size_t triangles = 1'000'000;
  double spacing = 0.01;
  int frames = 10, rounds = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--triangles") triangles = size_t(std::stod(v));
    if (k == "--spacing") spacing = std::stod(v);
    if (k == "--frames") frames = std::stoi(v);
    if (k == "--rounds") rounds = std::stoi(v);
  }
  try {
    fieldBuild(triangles, spacing);
    auto context = GLContext::create();
    std::printf("GL renderer: %s\n", context->info().renderer.c_str());
    meshAgainstAnalytic(frames, rounds);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "collider_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
