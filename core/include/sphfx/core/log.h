#pragma once
/// @file log.h
/// @brief Logging to stderr and a single-line progress display for long work.

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

namespace sphfx {

enum class LogLevel { Quiet = 0, Info = 1, Verbose = 2 };

/// Sets the global log level (default Info).
void setLogLevel(LogLevel level);
LogLevel logLevel();

/// Prints "sphfx: <message>" to stderr at Info level or above.
void logInfo(std::string_view message);
/// Prints "sphfx: warning: <message>" to stderr unless Quiet.
void logWarning(std::string_view message);
/// Prints at Verbose level only.
void logVerbose(std::string_view message);

/// A progress line for work of `total` items. On a terminal it redraws one line (carriage return);
/// otherwise (CI logs, pipes) it prints at most one line every few seconds. Thread-compatible, not
/// thread-safe: call update() from one thread.
class Progress {
 public:
  Progress(std::string label, int64_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Reports `done` items finished, with an optional detail text (rates, current item).
  void update(int64_t done, std::string_view detail = {});
  /// Logs `message` as a warning on a line of its own (a terminal's progress line is redrawn after it).
  void warn(std::string_view message);
  /// Ends the line (prints the final state once).
  void finish(std::string_view detail = {});

 private:
  void print(int64_t done, std::string_view detail, bool final);

  std::string label_;
  int64_t total_;
  int64_t done_ = 0;
  bool finished_ = false;
  bool tty_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point lastPrint_;
};

/// Formats seconds as "1m23s" / "4.2s".
std::string formatDuration(double seconds);

}  // namespace sphfx
