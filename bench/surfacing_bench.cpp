// Surfacing benchmark: one frame of about a million particles per run, one method per process (so that
// the peak resident memory, getrusage ru_maxrss, belongs to that method).
//
//   surfacing_bench --method zhu-bridson [--particles 1000000] [--cache FILE] [--threads T] [--repeat N]
//
// Input: the particle cache FILE (e.g. a dam-break frame) when given, else a generated dam-break-like
// set: a collapsing column (sheared lattice), a thin surge along the floor and scattered splash particles.
#include <fmt/format.h>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <thread>

#include "sphfx/core/error.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/surfacing/surfacing.h"

namespace {

using namespace sphfx;

/// About `target` particles shaped like a dam break a moment after the gate opened, spacing `s`.
ParticleFrame damBreakLike(size_t target) {
  // Column of 1 x 0.5 x 1.2 units plus a surge of ~10 % and splash of ~5 %: pick s from the volume.
  const double volume = 1.0 * 0.5 * 1.2 * 1.15;
  const double s = std::cbrt(volume / double(target));
  ParticleFrame f;
  f.particleSpacing = s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  auto add = [&](double x, double y, double z) { f.position.push_back({float(x), float(y), float(z)}); };
  const int nx = int(1.0 / s), ny = int(0.5 / s), nz = int(1.2 / s);
  for (int k = 0; k < nz; ++k) {
    const double z = (k + 0.5) * s, h = z / 1.2;
    const double shear = 0.3 * (1 - h) * (1 - h);  // the foot runs out, the top lags
    const int rowLength = int(nx * (1 - 0.35 * h * h));
    for (int i = 0; i < rowLength; ++i)
      for (int j = 0; j < ny; ++j) add((i + 0.5) * s + shear, (j + 0.5) * s, z);
  }
  // Surge: a tongue 1.3 units long, thinning from 0.12 to one spacing.
  for (double x = 1.3; x < 2.6; x += s) {
    const double thick = std::max(s, 0.12 * (2.6 - x) / 1.3);
    for (double z = 0.5 * s; z < thick; z += s)
      for (int j = 0; j < ny; ++j) add(x, (j + 0.5) * s, z);
  }
  // Splash: isolated particles and small clusters above the front.
  const size_t splash = f.position.size() / 20;
  for (size_t n = 0; n < splash; ++n) add(2.2 + 0.6 * u(rng), 0.5 * u(rng), 0.05 + 0.4 * u(rng) * u(rng));
  f.velocity.assign(f.position.size(), {0, 0, 0});
  return f;
}

double peakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string methodText = "zhu-bridson", cache;
  size_t particles = 1000000;
  int threads = int(std::thread::hardware_concurrency()), repeat = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--method")
      methodText = v;
    else if (a == "--particles")
      particles = std::stoul(v);
    else if (a == "--cache")
      cache = v;
    else if (a == "--threads")
      threads = std::stoi(v);
    else if (a == "--repeat")
      repeat = std::stoi(v);
    else {
      std::fprintf(stderr, "surfacing_bench: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  try {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    const auto dir = std::filesystem::temp_directory_path() / fmt::format("sphfx_surf_bench_{}", ::getpid());
    std::string input = cache;
    if (input.empty()) {
      input = (dir / "particles.0001.vdb").string();
      writeParticleCache(input, damBreakLike(particles));
    }
    const ParticleFrame frame = readParticleCache(input);
    Scene scene;
    sceneSchema().setDefaults(scene);
    surfacing::SurfaceOverrides overrides;
    overrides.method = surfacing::parseMethod(methodText);
    auto params = surfacing::resolveParams(frame.particleSpacing, scene.surface, overrides);
    params.surfaceOffset = surfacing::calibrateOffset(params);
    double best = 1e30;
    surfacing::FrameStats stats;
    for (int r = 0; r < repeat; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      stats =
          surfacing::surfaceFrame(input, (dir / "surface.vdb").string(), (dir / "mesh.ply").string(), params);
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::printf(
        "method %s input %s particles %zu spacing %.5g threads %d seconds_per_frame %.3f "
        "particles_per_core_second %.3g active_voxels %llu triangles %zu peak_rss_mib %.0f\n",
        methodText.c_str(), cache.empty() ? "generated-dam-break" : cache.c_str(), stats.particles,
        frame.particleSpacing, threads, best, double(stats.particles) / (best * threads),
        (unsigned long long)stats.activeVoxels, stats.triangles, peakMemoryMiB());
    std::filesystem::remove_all(dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surfacing_bench: %s\n", e.what());
    return exitCodeFor(e);
  }
  return 0;
}
