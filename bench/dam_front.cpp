// The dam-break front of every cached frame of a shot: the (1 + n/1000)-th largest x plus half a spacing
// (the study's front, study/measure.cpp), as "frame time front" lines, for comparing runs
// (bench/sensitivity.sh).
//
//   dam_front SHOT SPACING
#include <algorithm>
#include <cstdio>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "sphfx/core/frame_files.h"
#include "sphfx/core/particle_cache.h"

int main(int argc, char** argv) {
  using namespace sphfx;
  if (argc != 3) {
    std::fprintf(stderr, "usage: dam_front SHOT SPACING\n");
    return 2;
  }
  try {
    const std::string shot = argv[1];
    const double spacing = std::stod(argv[2]);
    for (int frame : listFrames(shot + "/cache", "particles", "vdb")) {
      const ParticleFrame f = readParticleCache(particleCachePath(shot, frame));
      if (f.size() == 0) continue;
      std::vector<float> x;
      for (const auto& p : f.position) x.push_back(p[0]);
      const size_t k = 1 + x.size() / 1000;
      std::nth_element(x.begin(), x.begin() + long(k - 1), x.end(), std::greater<float>());
      std::printf("%d %.6f %.6f\n", frame, f.time, x[k - 1] + 0.5 * spacing);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dam_front: %s\n", e.what());
    return 1;
  }
  return 0;
}
