#include "pass_timer.h"

#include "sphfx/gpu/gl.h"

namespace sphfx::sim {

// Wall time between glFinish calls: GL_TIME_ELAPSED queries return nothing useful on llvmpipe (every
// pass read the same value), and the benchmark needs the split on llvmpipe first of all. Finishing per
// pass serialises the GPU, so timed runs are slower; the benchmark takes its rate from an untimed run.
PassTimer::~PassTimer() = default;

void PassTimer::begin(const char* pass) {
  if (!enabled_) return;
  end();
  glFinish();
  current_ = pass;
  start_ = std::chrono::steady_clock::now();
  open_ = true;
}

void PassTimer::end() {
  if (!open_) return;
  glFinish();
  seconds_[current_] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  open_ = false;
}

void PassTimer::collect() {
  end();
}

}  // namespace sphfx::sim
