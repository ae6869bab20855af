// A resting column's pressure against rho0 g (H - y), frame by frame and averaged over time: for every
// cached frame the study's `pressure_l2` and `pressure_profile_l2` (study/src/metrics.h), then, over the
// frames from FROM seconds on (default: the last frame only), the profile error of the time-averaged slab
// means and each slab's mean pressure over its reference, floor first. H is the first fluid block's top and
// h the kernel radius, both from the scene the shot's manifest records; the cache must store density and
// pressure. A WCSPH column that starts unloaded rings at about 4 H / c, so cache at a frame rate that
// resolves that period to see it (docs/validation.md, "Known limits").
//
//   hydrostatic_profile SHOT [FROM]
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "metrics.h"
#include "sphfx/core/frame_files.h"
#include "sphfx/core/manifest.h"
#include "sphfx/core/particle_cache.h"
#include "sphfx/core/scene.h"

int main(int argc, char** argv) {
  using namespace sphfx;
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: hydrostatic_profile SHOT [FROM]\n");
    return 2;
  }
  try {
    const std::string shot = argv[1];
    const ManifestJson m = readManifest(shot);
    if (!m.contains("simulate") || !m["simulate"].contains("scene"))
      throw std::runtime_error(manifestPath(shot) + ": no simulate.scene");
    const Scene scene = parseScene(m["simulate"]["scene"], manifestPath(shot) + " (simulate.scene)");
    const double rho0 = scene.fluid.restDensity, g = -scene.gravity[1], h = scene.kernelRadius();
    const double H = scene.fluid.blocks.front().max[1];
    const std::vector<int> frames = listFrames(shot + "/cache", "particles", "vdb");
    if (frames.empty()) throw std::runtime_error(shot + ": no cache frames");
    double from = argc == 3 ? std::stod(argv[2]) : -1;
    study::PressureSlabs average(rho0, g, H, h);
    int averaged = 0;
    std::printf("# frame time pressure_l2 pressure_profile_l2\n");
    for (size_t k = 0; k < frames.size(); ++k) {
      const ParticleFrame f = readParticleCache(particleCachePath(shot, frames[k]));
      const study::HydrostaticError e = study::hydrostaticError(f, rho0, g, H, h);
      std::printf("%d %.4f %.4f %.4f\n", frames[k], f.time, e.pressureL2, e.profileL2);
      if (from < 0 && k + 1 == frames.size()) from = f.time;
      if (from >= 0 && f.time >= from - 1e-9) {
        average.add(f);
        ++averaged;
      }
    }
    std::printf(
        "# time-averaged over %d frames from %.4f s: profile error %.4f; p / p_ref per slab of %.4f m:",
        averaged, from, average.profileError(), average.slabHeight());
    for (double r : average.ratios()) std::printf(" %.3f", r);
    std::printf("\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hydrostatic_profile: %s\n", e.what());
    return 1;
  }
  return 0;
}
