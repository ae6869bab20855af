// WCSPH throughput on the dam break (scenes/dam_break.json, CFL-adaptive time step): particle-steps per
// second at ~30k, 100k and 300k particles, and the share of time per pass (wall time between glFinish
// calls, sim/pass_timer.h).
//
//   sim_bench [--scene FILE] [--particles N]... [--skip S] [--seconds S] [--fps F] [--timing 0|1] [--set
//   path=value]...
//
// --scene runs another scene (default scenes/dam_break.json); with it, --particles 0 keeps the scene's
// own spacing; --skip runs S simulated seconds before the measured stretch. The spacing is chosen so that the
// column holds about N particles. A short stretch of simulated time is run (default 0.004 s, i.e. a few dozen
// CFL substeps at these resolutions) as frames of 1/F s, so that per-frame work (health pass, read-back) is
// included at about the rate of a real shot. The first frame (program warm-up, boundary sort) is excluded
// from the rate. Timing queries synchronise per pass, so the shares come from a second, separate run when
// --timing 1 (the default), and the rate from an untimed one.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <string>
#include <vector>

#include "simulator.h"
#include "sphfx/core/error.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"

namespace {

using namespace sphfx;

struct Options {
  std::vector<double> particles;
  double seconds = 0.004;
  double fps = 1000;
  double skip = 0;  // simulated seconds run before the measured stretch (not timed)
  bool timing = true;
  std::string scene = std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json";
  std::vector<std::string> sets;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--particles")
      o.particles.push_back(std::stod(v));
    else if (k == "--seconds")
      o.seconds = std::stod(v);
    else if (k == "--fps")
      o.fps = std::stod(v);
    else if (k == "--timing")
      o.timing = v != "0";
    else if (k == "--set")
      o.sets.push_back(v);
    else if (k == "--skip")
      o.skip = std::stod(v);
    else if (k == "--scene")
      o.scene = v;
    else
      throw std::runtime_error("unknown option " + k);
  }
  if (o.particles.empty()) o.particles = {3e4, 1e5, 3e5};
  return o;
}

Scene makeScene(const Options& o, double particles, int frames) {
  const std::string& path = o.scene;
  std::vector<std::string> sets = {fmt::format("time.fps={}", o.fps), "time.start_frame=0",
                                   fmt::format("time.end_frame={}", frames)};
  if (particles > 0) {  // the spacing that fills the first block with about that many particles
    const Scene base = loadScene(path);
    if (base.fluid.blocks.empty())
      throw InputError(path +
                       ": --particles N scales fluid.blocks[0], and the scene has no block (use "
                       "--particles 0, the scene's own spacing)");
    const FluidBlock& b = base.fluid.blocks.front();
    const double volume = (b.max[0] - b.min[0]) * (b.max[1] - b.min[1]) * (b.max[2] - b.min[2]);
    sets.push_back(fmt::format("fluid.spacing={:.6g}", std::cbrt(volume / particles)));
  }
  sets.insert(sets.end(), o.sets.begin(), o.sets.end());
  return loadScene(path, sets);
}

struct Result {
  double wall = 0;
  long substeps = 0;
  std::map<std::string, double> passes;
};

Result runOnce(const Scene& s, bool timing, int skipFrames) {
  sim::Simulator sim(s);
  for (int f = 0; f <= skipFrames; ++f) sim.advance();  // warm-up (shader caches) and skipped frames
  glFinish();
  sim.enableTiming(timing);
  Result r;
  const auto t0 = std::chrono::steady_clock::now();
  while (sim.frame() < s.time.endFrame) r.substeps += sim.advance().substeps;
  glFinish();
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.passes = sim.passSeconds();
  return r;
}

void run(const Options& o, double particles) {
  const int skipFrames = int(std::lround(o.skip * o.fps));
  const int frames = 1 + skipFrames + std::max(1, int(std::lround(o.seconds * o.fps)));
  const Scene s = makeScene(o, particles, frames);
  const auto n = double(countInitialParticles(s));
  const Result r = runOnce(s, false, skipFrames);
  std::printf("%9.0f %8.5f %8ld %8.2f %12.4g %10.3g\n", n, s.fluid.spacing, r.substeps, r.wall,
              n * double(r.substeps) / r.wall, double(r.substeps) / r.wall);
  if (o.timing) {
    const Result t = runOnce(s, true, skipFrames);
    double total = 0;
    for (const auto& [k, v] : t.passes) total += v;
    std::vector<std::pair<double, std::string>> sorted;
    for (const auto& [k, v] : t.passes) sorted.push_back({v, k});
    std::sort(sorted.rbegin(), sorted.rend());
    std::printf("          passes (timed run, glFinish per pass: %.2f s in passes of %.2f s):", total,
                t.wall);
    for (const auto& [v, k] : sorted) std::printf(" %s %.1f%%", k.c_str(), 100 * v / total);
    std::printf("\n          ms per substep:");
    for (const auto& [v, k] : sorted) std::printf(" %s %.2f", k.c_str(), 1e3 * v / double(t.substeps));
    std::printf("\n");
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    auto ctx = GLContext::create();
    std::printf("# renderer: %s\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    std::printf("# %s; %g s simulated in frames of 1/%g s after one warm-up frame\n", o.scene.c_str(),
                o.seconds, o.fps);
    std::printf("%9s %8s %8s %8s %12s %10s\n", "particles", "spacing", "substeps", "wall_s", "p-steps/s",
                "steps/s");
    for (double p : o.particles) run(o, p);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sim_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
