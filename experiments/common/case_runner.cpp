#include "common/case_runner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>

namespace rbc::case_runner {

namespace fs = std::filesystem;

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

double symmetric_unit(std::mt19937& g) { return 2.0 * (double(g()) / 4294967296.0) - 1.0; }

double window_mean(const std::vector<double>& t, const std::vector<double>& v, double from) {
  double s = 0;
  int n = 0;
  for (std::size_t k = 0; k < t.size() && k < v.size(); ++k)
    if (t[k] >= from - 1e-12) {
      s += v[k];
      ++n;
    }
  return n ? s / n : NAN;
}

CaseRun run_or_reuse(const Scene& scene, const std::string& out_dir, const CaseRunOptions& o) {
  CaseRun r;
  const fs::path out(out_dir);
  const fs::path failed = out / "failure.txt";
  auto read_failure = [&]() -> std::optional<std::string> {
    std::ifstream f(failed);
    std::string source, dt, why;
    if (!std::getline(f, source) || !std::getline(f, dt) || !std::getline(f, why)) return std::nullopt;
    if (source != scene.source || dt != num(scene.dt)) return std::nullopt;
    return why;
  };
  try {
    const std::optional<RunSummary> done = o.reuse ? read_finished_run(out.string(), scene) : std::nullopt;
    const std::optional<std::string> stopped = o.reuse && !done ? read_failure() : std::nullopt;
    if (stopped) throw RunFailure(*stopped);
    fs::remove(failed);
    const bool resume = o.resume && !done && fs::exists(out / "checkpoint.bin");
    r.summary = done ? *done
                     : run_scene(scene, {.out_dir = out.string(), .threads = o.threads, .progress = o.progress, .label = o.label,
                                         .checkpoint_wall = 300, .resume = resume});
  } catch (const RunFailure& e) {
    r.failure = e.what();
    std::replace(r.failure.begin(), r.failure.end(), '\n', ' ');
    std::ofstream(failed) << scene.source << "\n" << num(scene.dt) << "\n" << r.failure << "\n";
  }
  return r;
}

}  // namespace rbc::case_runner
