#pragma once
/// @file cache_writer.h
/// @brief A writer thread with a bounded queue: the simulation hands over finished frames and goes on;
/// the thread writes each cache (atomically, through core's writeParticleCache), then the restart file,
/// then runs a callback (manifest update). An error on the thread is rethrown by the next push/finish.

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "simulator.h"
#include "sphfx/core/particle_cache.h"

namespace sphfx::sim {

struct FrameOutput {
  std::optional<ParticleFrame> cache;  ///< absent: frame outside the written range
  std::string cachePath;
  SimulatorState restart;
  std::string restartPath;
  uint64_t sceneHash = 0;
  FrameStats stats;
};

class CacheWriter {
 public:
  using Written = std::function<void(const FrameOutput&)>;
  CacheWriter(size_t capacity, Written onWritten);
  /// Stops the thread; pending frames are still written. Errors are dropped here (use finish()).
  ~CacheWriter();
  CacheWriter(const CacheWriter&) = delete;
  CacheWriter& operator=(const CacheWriter&) = delete;

  /// Queues a frame; waits while the queue is full. Rethrows an earlier write error.
  void push(FrameOutput frame);
  /// Waits until everything queued is written. Rethrows a write error.
  void finish();

 private:
  void run();
  void rethrow();

  size_t capacity_;
  Written onWritten_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<FrameOutput> queue_;
  bool busy_ = false, stop_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace sphfx::sim
