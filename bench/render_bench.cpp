// Seconds per 1920x1080 frame of the renderer on the current GL (llvmpipe without a GPU): particles
// mode with 1M sphere impostors, surface mode with a water mesh of a similar triangle count. Generated
// inputs (a jittered lattice in a dam-break tank, a soup of spheres) so the bench needs no shot.
// Each figure is wall seconds per frame and CPU seconds per frame (all threads of the process: llvmpipe
// rasterises on every core), so a busy shared machine shows up as wall >> CPU / cores.
//   render_bench [--particles N] [--size WxH] [--samples S] [--frames F] [--gl BACKEND] [--out DIR]
//                [--only particles|surface]
#include <fmt/format.h>

#include <sys/resource.h>
#include <chrono>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "renderer.h"
#include "sphfx/core/error.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"
#include "sphfx/render/render_shot.h"

using namespace sphfx;
using namespace sphfx::render;

namespace {

struct Args {
  int particles = 1000000, width = 1920, height = 1080, samples = 4, frames = 3;
  std::string gl = "auto", out, only;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--particles")
      a.particles = std::stoi(v);
    else if (k == "--size")
      std::tie(a.width, a.height) = parseImageSize(v);
    else if (k == "--samples")
      a.samples = std::stoi(v);
    else if (k == "--frames")
      a.frames = std::stoi(v);
    else if (k == "--gl")
      a.gl = v;
    else if (k == "--out")
      a.out = v;
    else if (k == "--only" && (v == "particles" || v == "surface"))
      a.only = v;
    else
      throw InputError("unknown option " + k);
  }
  return a;
}

/// A dam-break-like column of N particles in a 1 x 0.6 x 0.4 m tank, spacing from N.
std::vector<ParticleInstance> makeParticles(int n, float& spacing) {
  const double volume = 0.4 * 0.5 * 0.4;
  spacing = float(std::cbrt(volume / n));
  const int nx = int(0.4 / spacing), ny = int(0.5 / spacing), nz = int(0.4 / spacing);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-0.1f, 0.1f);
  std::vector<ParticleInstance> ps;
  ps.reserve(size_t(n));
  for (int i = 0; i < nx && int(ps.size()) < n; ++i)
    for (int j = 0; j < ny && int(ps.size()) < n; ++j)
      for (int k = 0; k < nz && int(ps.size()) < n; ++k)
        ps.push_back({{(i + 0.5f + jitter(rng)) * spacing, (j + 0.5f + jitter(rng)) * spacing,
                       (k + 0.5f + jitter(rng)) * spacing},
                      float(j) / float(ny) * 3.0f});
  return ps;
}

/// A soup of overlapping spheres filling the same column: ~N/2 triangles, like a dense surfaced mesh.
TriangleMesh makeSoup(int triangles) {
  TriangleMesh soup;
  const int per = 2 * 24 * 48, count = std::max(1, triangles / per);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int s = 0; s < count; ++s) {
    const TriangleMesh m = makeUvSphere({0.05 + 0.3 * u(rng), 0.05 + 0.4 * u(rng), 0.05 + 0.3 * u(rng)},
                                        0.03 + 0.05 * u(rng), 24, 48);
    const uint32_t base = uint32_t(soup.positions.size());
    soup.positions.insert(soup.positions.end(), m.positions.begin(), m.positions.end());
    soup.normals.insert(soup.normals.end(), m.normals.begin(), m.normals.end());
    for (auto t : m.triangles) soup.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  return soup;
}

double cpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Timing {
  double wall = 0, cpu = 0;  ///< seconds per frame
};

template <class F>
Timing secondsPerFrame(int frames, F render) {
  render();  // warm-up: shader compile and first allocations are not per-frame costs
  const auto start = std::chrono::steady_clock::now();
  const double cpu0 = cpuSeconds();
  for (int i = 0; i < frames; ++i) render();
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / frames,
          (cpuSeconds() - cpu0) / frames};
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a = parse(argc, argv);
    auto ctx = GLContext::create({parseGLBackend(a.gl), false});
    Renderer renderer(a.width, a.height, a.samples);
    Stage stage;
    stage.domain = {{0, 0, 0}, {1.0, 0.6, 0.4}};
    Scene scene;
    scene.domain = stage.domain;
    scene.render.camera.reset();
    const CameraView camera = sceneCamera(scene, 0, double(a.width) / a.height);
    float spacing = 0;
    const std::vector<ParticleInstance> ps = makeParticles(a.particles, spacing);
    ParticleStyle style;
    style.radius = spacing / 2;
    style.heightMax = 0.6f;
    Image pImg, sImg;
    fmt::print("renderer: {}\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    fmt::print("image: {}x{}, {} MSAA samples (requested {})\n", a.width, a.height, renderer.samples(),
               a.samples);
    if (a.only != "surface") {
      const Timing t =
          secondsPerFrame(a.frames, [&] { pImg = renderer.renderParticles(ps, style, stage, camera); });
      const Renderer::ParticleCounts counts = renderer.lastParticleCounts();
      fmt::print("particles: {} impostors, radius {:.4f} m: {:.3f} s/frame wall, {:.3f} s/frame CPU\n",
                 ps.size(), style.radius, t.wall, t.cpu);
      fmt::print(
          "  {} points ({} occluders, {} left after the occlusion cull), {} quads, {} outside the view"
          " (max point size {})\n",
          counts.points, counts.occluders, counts.visible, counts.quads, counts.culled,
          renderer.maxPointSize());
      const Timing te = secondsPerFrame(a.frames, [&] { (void)encodeSrgb8(pImg); });
      fmt::print("sRGB encode: {:.3f} s/frame wall, {:.3f} s/frame CPU\n", te.wall, te.cpu);
    }
    if (a.only != "particles") {
      const TriangleMesh soup = makeSoup(a.particles);
      const Timing t = secondsPerFrame(a.frames, [&] { sImg = renderer.renderSurface(soup, stage, camera); });
      fmt::print("surface: {} triangles: {:.3f} s/frame wall, {:.3f} s/frame CPU\n", soup.triangles.size(),
                 t.wall, t.cpu);
    }
    if (!a.out.empty()) {
      if (!pImg.rgba.empty()) writePng(a.out + "/bench_particles.png", encodeSrgb8(pImg));
      if (!sImg.rgba.empty()) writePng(a.out + "/bench_surface.png", encodeSrgb8(sImg));
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "render_bench: {}\n", e.what());
    return 1;
  }
  return 0;
}
