#pragma once
// A progress line on stderr for long runs: simulated time, steps per second and the estimated
// time left. On a terminal it rewrites one line; otherwise (CI, logs) it prints a line at most
// every 10 s.
#include <chrono>
#include <string>

namespace rbc {

class ProgressMeter {
 public:
  ProgressMeter(std::string label, long total_steps, double t_end, bool enabled);
  void update(long step, double t);
  void resumed_at(long step) { first_ = step; }  // a resumed run: rates count from here
  void finish(long step, double t);
  double elapsed_seconds() const;

 private:
  void print(long step, double t, bool final);
  std::string label_;
  long total_, first_ = 0;
  double t_end_;
  bool enabled_, tty_;
  std::chrono::steady_clock::time_point start_, last_;
};

std::string format_duration(double seconds);  // "1h02m", "3m12s", "4.2s"

}  // namespace rbc
