#include "cache_writer.h"

#include "restart_file.h"

namespace sphfx::sim {

CacheWriter::CacheWriter(size_t capacity, Written onWritten)
    : capacity_(std::max<size_t>(capacity, 1)),
      onWritten_(std::move(onWritten)),
      thread_([this] { run(); }) {}

CacheWriter::~CacheWriter() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void CacheWriter::rethrow() {
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void CacheWriter::push(FrameOutput frame) {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return queue_.size() < capacity_ || error_; });
  rethrow();
  queue_.push_back(std::move(frame));
  changed_.notify_all();
}

void CacheWriter::finish() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [&] { return (queue_.empty() && !busy_) || error_; });
  rethrow();
}

void CacheWriter::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return !queue_.empty() || stop_; });
    if (queue_.empty()) return;
    FrameOutput f = std::move(queue_.front());
    queue_.pop_front();
    busy_ = true;
    lock.unlock();
    try {
      // Cache first, then the restart file: a restart file always means its frame is complete.
      if (f.cache) writeParticleCache(f.cachePath, *f.cache);
      if (!f.restartPath.empty()) writeRestartFile(f.restartPath, f.restart, f.sceneHash);
      if (onWritten_) onWritten_(f);
    } catch (...) {
      lock.lock();
      error_ = std::current_exception();
      busy_ = false;
      queue_.clear();
      changed_.notify_all();
      continue;
    }
    lock.lock();
    busy_ = false;
    changed_.notify_all();
  }
}

}  // namespace sphfx::sim
