#pragma once
// Wall-clock accounting for the semi-implicit coupling's cost breakdown (SemiImplicitMembraneStep::Cost,
// read by bench/bench_channel.cpp): not part of the method. lap(into) adds the seconds since the
// watch started, restarted or last lapped to `into`, and starts again.
#include <chrono>

namespace rbc::detail {

class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(clock::now() - start_).count(); }
  void restart() { start_ = clock::now(); }
  void lap(double& into) {
    const clock::time_point now = clock::now();
    into += std::chrono::duration<double>(now - start_).count();
    start_ = now;
  }

 private:
  using clock = std::chrono::steady_clock;
  clock::time_point start_ = clock::now();
};

}  // namespace rbc::detail
