// Surfacing benchmark: one frame per run, one method per process (so that the peak resident memory,
// getrusage ru_maxrss, belongs to that method). Times sphfx::surfacing::surfaceFrame, the code path of
// `sphfx surface` (read the cache, level set, mesh, write the VDB and the PLY), after calibration.
//
//   surfacing_bench --method M [--threads T] [--repeat N] [--smooth N] [--voxel-factor F] INPUT
//   INPUT: --cache FILE                       a particle cache as it is (e.g. a simulated dam-break frame)
//          --refine-from FILE [--particles N] that cache refined to about N particles (see refine())
//                             [--refined-out FILE]  and the refined frame kept as a cache file
//          --generate [--particles N]         a generated dam-break-like frame (the first benchmark input)
//
// The refined and generated frames are written as normal cache files and surfaced from there.
#include <fmt/format.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <thread>

#include "sphfx/core/error.h"
#include "sphfx/core/huge_pages.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/surfacing/surfacing.h"

namespace {

using namespace sphfx;

/// About `target` particles shaped like a dam break a moment after the gate opened.
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

/// A simulated frame refined to about `target` particles: m = round(cbrt(target / n)) per axis; each
/// particle of spacing s becomes the m^3 points of a cubic sub-lattice of spacing s/m filling its own
/// s^3 cell (centred on it), each point jittered uniformly by up to +-0.1 s/m (fixed seed), with the
/// parent's velocity. The fluid's volume and shape stay those of the simulation, at m^3 times the
/// particles and 1/m the spacing. Written in the parent's storage order, so the result is reproducible.
ParticleFrame refine(const ParticleFrame& coarse, size_t target) {
  const int m = std::max(1, int(std::lround(std::cbrt(double(target) / double(coarse.size())))));
  const double s = coarse.particleSpacing, fine = s / m;
  ParticleFrame f;
  f.frame = coarse.frame;
  f.time = coarse.time;
  f.particleSpacing = fine;
  f.position.reserve(coarse.size() * m * m * m);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.1 * fine, 0.1 * fine);
  for (size_t n = 0; n < coarse.size(); ++n)
    for (int a = 0; a < m; ++a)
      for (int b = 0; b < m; ++b)
        for (int c = 0; c < m; ++c) {
          const auto& p = coarse.position[n];
          const int idx[3] = {a, b, c};
          std::array<float, 3> q{};
          for (int k = 0; k < 3; ++k) q[k] = float(p[k] + ((idx[k] + 0.5) / m - 0.5) * s + jitter(rng));
          f.position.push_back(q);
          f.velocity.push_back(coarse.velocity[n]);
        }
  return f;
}

double peakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;
}

double cpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  auto sec = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return sec(usage.ru_utime) + sec(usage.ru_stime);
}

int usage() {
  std::fprintf(stderr,
               "usage: surfacing_bench [--method M] [--threads T] [--repeat N] [--smooth N] "
               "[--voxel-factor F] (--cache FILE | --refine-from FILE [--particles N] [--refined-out FILE] "
               "| --generate [--particles N])\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  reexecWithHugePageMalloc(argv);  // as the sphfx executable does
  std::string methodText = "zhu-bridson", cache, refineFrom, refinedOut;
  bool generate = false;
  size_t particles = 1000000;
  int threads = int(std::thread::hardware_concurrency()), repeat = 1;
  surfacing::SurfaceOverrides overrides;
  double voxelFactor = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--generate") {
      generate = true;
      continue;
    }
    if (i + 1 >= argc) return usage();
    const std::string v = argv[++i];
    if (a == "--method")
      methodText = v;
    else if (a == "--particles")
      particles = std::stoul(v);
    else if (a == "--cache")
      cache = v;
    else if (a == "--refine-from")
      refineFrom = v;
    else if (a == "--refined-out")
      refinedOut = v;
    else if (a == "--threads")
      threads = std::stoi(v);
    else if (a == "--repeat")
      repeat = std::stoi(v);
    else if (a == "--smooth")
      overrides.smoothIterations = std::stoi(v);
    else if (a == "--voxel-factor")
      voxelFactor = std::stod(v);
    else
      return usage();
  }
  if (int(generate) + int(!cache.empty()) + int(!refineFrom.empty()) != 1) return usage();
  try {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
    const auto dir = std::filesystem::temp_directory_path() / fmt::format("sphfx_surf_bench_{}", ::getpid());
    std::filesystem::create_directories(dir);
    std::string input = cache, inputName = cache;
    if (generate) {
      input = (dir / "particles.0001.vdb").string();
      writeParticleCache(input, damBreakLike(particles));
      inputName = "generated-dam-break";
    } else if (!refineFrom.empty()) {
      input = refinedOut.empty() ? (dir / "particles.0001.vdb").string() : refinedOut;
      writeParticleCache(input, refine(readParticleCache(refineFrom), particles));
      inputName = "refined " + refineFrom;
    }
    const ParticleFrame frame = readParticleCache(input);
    Scene scene;
    sceneSchema().setDefaults(scene);
    overrides.method = surfacing::parseMethod(methodText);
    if (voxelFactor > 0) overrides.voxelSize = voxelFactor * frame.particleSpacing;
    auto params = surfacing::resolveParams(frame.particleSpacing, scene.surface, overrides);
    params.surfaceOffset = surfacing::calibrateOffset(params);
    double best = 1e30, bestCpu = 0;
    surfacing::FrameStats stats;
    for (int r = 0; r < repeat; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      const double c0 = cpuSeconds();
      const auto s =
          surfacing::surfaceFrame(input, (dir / "surface.vdb").string(), (dir / "mesh.ply").string(), params);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (seconds < best) {
        best = seconds;
        bestCpu = cpuSeconds() - c0;
        stats = s;
      }
    }
    std::string stages;
    for (const auto& [name, sec] : stats.stageSeconds) stages += fmt::format(" {} {:.3f}", name, sec);
    std::printf(
        "method %s input %s particles %zu spacing %.5g voxel %.5g threads %d seconds_per_frame %.3f "
        "cpu_seconds %.3f particles_per_core_second %.3g active_voxels %llu triangles %zu peak_rss_mib %.0f\n"
        "stages:%s\n",
        methodText.c_str(), inputName.c_str(), stats.particles, frame.particleSpacing, params.voxelSize,
        threads, best, bestCpu, double(stats.particles) / (best * threads),
        (unsigned long long)stats.activeVoxels, stats.triangles, peakMemoryMiB(), stages.c_str());
    std::filesystem::remove_all(dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surfacing_bench: %s\n", e.what());
    return exitCodeFor(e);
  }
  return 0;
}
