// DFSPH against WCSPH on the dam break (scenes/dam_break.json, a = 0.2, n^2 = 2), in one process and one
// GL context: wall time to simulate the requested seconds, substeps, mean dt, DFSPH iterations and
// errors, and the surge front against Martin & Moyce (relative RMS over T <= 3).
//
//   sim_dfsph_bench [--seconds S] [--spacing D]... [--solver wcsph|dfsph]... [--set path=value]...
//
// Every --set applies to every run (e.g. time.dt_max=0.02); --dfsph-set / --wcsph-set to one solver.
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include "metrics.h"
#include "references.h"
#include "simulator.h"
#include "sphfx/core/scene.h"
#include "sphfx/gpu/gl.h"
#include "sphfx/gpu/gl_context.h"

namespace {

using namespace sphfx;

struct Options {
  double seconds = 1.0;
  std::vector<double> spacings;
  std::vector<std::string> solvers, sets, dfsphSets, wcsphSets;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--seconds")
      o.seconds = std::stod(v);
    else if (k == "--spacing")
      o.spacings.push_back(std::stod(v));
    else if (k == "--solver")
      o.solvers.push_back(v);
    else if (k == "--set")
      o.sets.push_back(v);
    else if (k == "--dfsph-set")
      o.dfsphSets.push_back(v);
    else if (k == "--wcsph-set")
      o.wcsphSets.push_back(v);
    else
      throw std::runtime_error("unknown option " + k);
  }
  if (o.spacings.empty()) o.spacings = {0.01};
  if (o.solvers.empty()) o.solvers = {"dfsph", "wcsph"};
  return o;
}

double statOf(const sim::FrameStats& f, const char* key) {
  for (const auto& [k, v] : f.solverStats)
    if (k == key) return v;
  return 0;
}

void run(const Options& o, const std::string& solver, double spacing, const study::MartinMoyce& ref) {
  std::vector<std::string> sets = {"solver.method=" + solver, fmt::format("fluid.spacing={}", spacing)};
  sets.insert(sets.end(), o.sets.begin(), o.sets.end());
  const auto& extra = solver == "dfsph" ? o.dfsphSets : o.wcsphSets;
  sets.insert(sets.end(), extra.begin(), extra.end());
  Scene s = loadScene(std::string(SPHFX_SOURCE_DIR) + "/scenes/dam_break.json", sets);
  s.time.endFrame = s.time.startFrame + int(std::lround(o.seconds * s.time.fps));
  sim::Simulator sim(s);
  const double a = 0.2, g = 9.81;
  std::vector<study::CurveSample> front;
  double wall = 0, dtSum = 0, pIt = 0, dIt = 0, errMean = 0, errMax = 0;
  long substeps = 0;
  int frames = 0;
  const std::clock_t cpu0 = std::clock();  // process CPU time: llvmpipe's worker threads included
  while (sim.frame() < s.time.endFrame) {
    const auto t0 = std::chrono::steady_clock::now();
    const sim::FrameStats f = sim.advance();
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    substeps += f.substeps;
    dtSum += f.dtMean * f.substeps;
    pIt += statOf(f, "pressure_iterations_mean") * f.substeps;
    dIt += statOf(f, "divergence_iterations_mean") * f.substeps;
    errMean += statOf(f, "density_error_mean") * f.substeps;
    errMax = std::max(errMax, statOf(f, "density_error_max"));
    ++frames;
    front.push_back(
        {s.frameTime(sim.frame()) * std::sqrt(2 * g / a), study::surgeFront(sim.cacheFrame(), 0.0) / a});
  }
  const study::CurveError e = study::relativeError(front, ref.front, 3.0);
  const double n = double(substeps);
  const double cpu = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
  std::printf("%-6s %8.4f %8u %7.2f %7.2f %7ld %9.3e %7.2f %7.2f %9.2e %9.2e %8.4f %8.4f\n", solver.c_str(),
              spacing, sim.particleCount(), wall, cpu, substeps, dtSum / n, pIt / n, dIt / n, errMean / n,
              errMax, e.rms, e.max);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    auto ctx = GLContext::create();
    std::printf("# renderer: %s\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    std::printf("# simulated seconds: %g\n", o.seconds);
    std::printf("%-6s %8s %8s %7s %7s %7s %9s %7s %7s %9s %9s %8s %8s\n", "solver", "spacing", "particles",
                "wall_s", "cpu_s", "steps", "dt_mean", "p_iter", "d_iter", "rho_err", "rho_max", "frontRMS",
                "frontMax");
    const auto ref = study::MartinMoyce::load(study::referenceDirectory());
    for (double spacing : o.spacings)
      for (const auto& solver : o.solvers) run(o, solver, spacing, ref);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sim_dfsph_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
