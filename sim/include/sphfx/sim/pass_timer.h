#pragma once
/// @file pass_timer.h
/// @brief GPU time per named pass (GL_TIME_ELAPSED queries), for the benchmark. Off: free.

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
  /// Waits for the queries issued so far and adds them up. Call once per frame (it synchronises).
  void collect();
  /// Seconds of GPU time per pass since enable().
  const std::map<std::string, double>& seconds() const { return seconds_; }

 private:
  bool enabled_ = false;
  bool open_ = false;
  std::vector<std::pair<uint32_t, std::string>> pending_;
  std::vector<uint32_t> free_;
  std::map<std::string, double> seconds_;
};

}  // namespace sphfx::sim
