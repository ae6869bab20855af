#include "sphfx/sim/pass_timer.h"

#include "sphfx/core/gl.h"

namespace sphfx::sim {

PassTimer::~PassTimer() {
  for (auto& [q, name] : pending_) free_.push_back(q);
  if (!free_.empty()) glDeleteQueries(GLsizei(free_.size()), free_.data());
}

void PassTimer::begin(const char* pass) {
  if (!enabled_) return;
  end();
  GLuint q = 0;
  if (free_.empty()) {
    glGenQueries(1, &q);
  } else {
    q = free_.back();
    free_.pop_back();
  }
  glBeginQuery(GL_TIME_ELAPSED, q);
  pending_.emplace_back(q, pass);
  open_ = true;
}

void PassTimer::end() {
  if (!open_) return;
  glEndQuery(GL_TIME_ELAPSED);
  open_ = false;
}

void PassTimer::collect() {
  end();
  for (auto& [q, name] : pending_) {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(q, GL_QUERY_RESULT, &ns);
    seconds_[name] += double(ns) * 1e-9;
    free_.push_back(q);
  }
  pending_.clear();
}

}  // namespace sphfx::sim
