#include "io/progress.hpp"

#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace rbc {

std::string format_duration(double s) {
  char buf[64];
  if (!std::isfinite(s)) return "?";
  if (s < 60) std::snprintf(buf, sizeof buf, "%.1fs", s);
  else if (s < 3600) std::snprintf(buf, sizeof buf, "%dm%02ds", int(s / 60), int(s) % 60);
  else std::snprintf(buf, sizeof buf, "%dh%02dm", int(s / 3600), (int(s) % 3600) / 60);
  return buf;
}

ProgressMeter::ProgressMeter(std::string label, long total_steps, double t_end, bool enabled)
    : label_(std::move(label)), total_(total_steps), t_end_(t_end), enabled_(enabled), tty_(isatty(2) != 0),
      start_(std::chrono::steady_clock::now()), last_(start_) {
  recent_.push_back({start_, 0});
}

double ProgressMeter::elapsed_seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressMeter::update(long step, double t) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_).count();
  if (since < (tty_ ? 0.5 : 10.0)) return;
  last_ = now;
  print(step, t, false);
}

void ProgressMeter::finish(long step, double t) {
  if (enabled_) print(step, t, true);
}

void ProgressMeter::print(long step, double t, bool final) {
  const auto now = std::chrono::steady_clock::now();
  const double el = std::chrono::duration<double>(now - start_).count();
  const double rate = el > 0 ? (step - first_) / el : 0;
  const double left = rate > 0 ? (total_ - step) / rate : INFINITY;
  // The rate over the lines of about the last minute: from the newest line at least
  // kRecentSeconds old (the start while the run is younger).
  while (recent_.size() > 1 && std::chrono::duration<double>(now - recent_[1].first).count() >= kRecentSeconds) recent_.pop_front();
  const double span = std::chrono::duration<double>(now - recent_.front().first).count();
  const double recent = span > 0 ? (step - recent_.front().second) / span : 0;
  recent_.push_back({now, step});
  char rates[96];
  if (final || span >= 0.9 * el)  // the window is the whole run: one rate says it
    std::snprintf(rates, sizeof rates, "%.0f steps/s", rate);
  else
    std::snprintf(rates, sizeof rates, "%.0f steps/s (last %.0f s: %.0f)", rate, span, recent);
  std::fprintf(stderr, "%s%s: t = %.4g / %.4g s (%5.1f %%), step %ld/%ld, %s, %s %s%s", tty_ ? "\r" : "", label_.c_str(), t,
               t_end_, 100.0 * step / std::max(1L, total_), step, total_, rates, final ? "wall" : "ETA",
               format_duration(final ? el : left).c_str(), (tty_ && !final) ? "   " : "\n");
  std::fflush(stderr);
}

}  // namespace rbc
