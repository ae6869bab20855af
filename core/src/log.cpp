#include "sphfx/core/log.h"

#include <unistd.h>

#include <fmt/format.h>
#include <cmath>
#include <cstdio>

namespace sphfx {
namespace {
LogLevel gLevel = LogLevel::Info;
}  // namespace

void setLogLevel(LogLevel level) {
  gLevel = level;
}
LogLevel logLevel() {
  return gLevel;
}

void logInfo(std::string_view message) {
  if (gLevel >= LogLevel::Info) std::fprintf(stderr, "sphfx: %.*s\n", int(message.size()), message.data());
}
void logWarning(std::string_view message) {
  if (gLevel >= LogLevel::Info)
    std::fprintf(stderr, "sphfx: warning: %.*s\n", int(message.size()), message.data());
}
void logVerbose(std::string_view message) {
  if (gLevel >= LogLevel::Verbose) std::fprintf(stderr, "sphfx: %.*s\n", int(message.size()), message.data());
}

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  if (seconds < 60) return fmt::format("{:.1f}s", seconds);
  const auto total = static_cast<long>(seconds + 0.5);
  if (total < 3600) return fmt::format("{}m{:02}s", total / 60, total % 60);
  return fmt::format("{}h{:02}m", total / 3600, (total / 60) % 60);
}

Progress::Progress(std::string label, int64_t total)
    : label_(std::move(label)),
      total_(total),
      tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      lastPrint_(start_ - std::chrono::hours(1)) {}

Progress::~Progress() {
  if (!finished_ && tty_ && gLevel >= LogLevel::Info) std::fputc('\n', stderr);
}

void Progress::update(int64_t done, std::string_view detail) {
  done_ = done;
  const auto now = std::chrono::steady_clock::now();
  // A terminal redraws cheaply; a log file gets a line every 5 s so CI output stays readable.
  const auto interval = tty_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(5000);
  if (now - lastPrint_ < interval) return;
  lastPrint_ = now;
  print(done, detail, false);
}

void Progress::warn(std::string_view message) {
  if (tty_ && gLevel >= LogLevel::Info) std::fputs("\r\033[K", stderr);
  logWarning(message);
  lastPrint_ = start_ - std::chrono::hours(1);  // redraw at the next update
}

void Progress::finish(std::string_view detail) {
  if (finished_) return;
  finished_ = true;
  print(total_, detail, true);
}

void Progress::print(int64_t done, std::string_view detail, bool final) {
  if (gLevel < LogLevel::Info) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string eta;
  if (!final && done > 0 && total_ > done)
    eta = " ETA " + formatDuration(elapsed * double(total_ - done) / double(done));
  const int pct = total_ > 0 ? int(100.0 * double(done) / double(total_)) : 100;
  const std::string line = fmt::format("{} {}/{} ({}%) {}{}{}", label_, done, total_, pct,
                                       formatDuration(elapsed), eta, detail.empty() ? "" : " | ");
  if (tty_)
    std::fprintf(stderr, "\r\033[K%s%.*s%s", line.c_str(), int(detail.size()), detail.data(),
                 final ? "\n" : "");
  else
    std::fprintf(stderr, "%s%.*s\n", line.c_str(), int(detail.size()), detail.data());
  std::fflush(stderr);
}

}  // namespace sphfx
