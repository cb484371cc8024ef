#pragma once
// A progress line on stderr for long runs: simulated time, steps per second and the estimated
// time left. On a terminal it rewrites one line; otherwise (CI, logs) it prints a line at most
// every 10 s. The rate is given twice: since the start (the estimate of the time left uses it)
// and over about the last minute (kRecentSeconds), which shows a machine that slows down or
// speeds up for minutes at a time (a shared or throttled machine;: one run's steps
// took 15.5 ms in some minutes and 24.7 ms in others, which the mean since the start hid).
#include <chrono>
#include <deque>
#include <string>
#include <utility>

namespace rbc {

class ProgressMeter {
 public:
  ProgressMeter(std::string label, long total_steps, double t_end, bool enabled);
  void update(long step, double t);
  void resumed_at(long step) {  // a resumed run: rates count from here
    first_ = step;
    recent_.assign(1, {start_, step});
  }
  void finish(long step, double t);
  double elapsed_seconds() const;

 private:
  void print(long step, double t, bool final);
  static constexpr double kRecentSeconds = 60;
  std::deque<std::pair<std::chrono::steady_clock::time_point, long>> recent_;  // (when, step) of the last lines
  std::string label_;
  long total_, first_ = 0;
  double t_end_;
  bool enabled_, tty_;
  std::chrono::steady_clock::time_point start_, last_;
};

std::string format_duration(double seconds);  // "1h02m", "3m12s", "4.2s"

}  // namespace rbc
