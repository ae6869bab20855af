#pragma once
/// @file pass_timer.h
/// @brief Time per named pass (glFinish around each pass, wall clock), for the benchmark. Off: free.

#include <chrono>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace sphfx::sim {

class PassTimer {
 public:
  PassTimer() = default;
  ~PassTimer();
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

  void enable(bool on) { enabled_ = on; }
  bool enabled() const { return enabled_; }
  /// Starts timing `pass` (ends the previous one). Queries do not nest.
  void begin(const char* pass);
  void end();
  /// Ends the open pass. Call once per frame.
  void collect();
  /// Seconds of GPU time per pass since enable().
  const std::map<std::string, double>& seconds() const { return seconds_; }

 private:
  bool enabled_ = false;
  bool open_ = false;
  std::string current_;
  std::chrono::steady_clock::time_point start_;
  std::map<std::string, double> seconds_;
};

}  // namespace sphfx::sim
