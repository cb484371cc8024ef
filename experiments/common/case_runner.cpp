#include "common/case_runner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "io/csv.hpp"
#include "mesh/channel_mesh.hpp"
#include "reference/uncertainty.hpp"

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

std::vector<std::pair<std::string, double>> u_readings(const std::string& series, double from, double scale) {
  const std::vector<std::string> columns = csv_header(series);
  const std::vector<double> t = csv_column(series, "t");
  std::vector<std::pair<std::string, double>> out;
  for (const auto& [id, column] : {std::pair{"p1_mean", "mean_velocity"}, std::pair{"nodal_mean", "nodal_mean_velocity"},
                                   std::pair{"plasma_flux", "plasma_flux_velocity"}, std::pair{"plasma_open", "plasma_open_velocity"}})
    if (std::find(columns.begin(), columns.end(), column) != columns.end()) {
      const double v = scale * window_mean(t, csv_column(series, column), from);
      if (std::isfinite(v)) out.emplace_back(id, v);  // an empty window measures nothing
    }
  return out;
}

std::pair<double, double> centroid_error(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& ref, double L) {
  double s = 0, sy = 0;
  for (std::size_t b = 0; b < a.size() && b < ref.size(); ++b) {
    double dx = a[b].x() - ref[b].x();
    dx = nearest_image(dx, L);
    const double dy = a[b].y() - ref[b].y();
    s += dx * dx + dy * dy;
    sy += dy * dy;
  }
  const double n = double(std::min(a.size(), ref.size()));
  return {std::sqrt(s / n), std::sqrt(sy / n)};
}

std::vector<Eigen::Vector2d> richardson_centroids(const std::vector<Eigen::Vector2d>& fine, const std::vector<Eigen::Vector2d>& coarse,
                                                  double L) {
  std::vector<Eigen::Vector2d> r;
  for (std::size_t b = 0; b < fine.size() && b < coarse.size(); ++b) {
    Eigen::Vector2d c = coarse[b];
    c.x() = fine[b].x() + nearest_image(c.x() - fine[b].x(), L);
    r.emplace_back(richardson_extrapolate(fine[b].x(), c.x(), 2, 1), richardson_extrapolate(fine[b].y(), c.y(), 2, 1));
  }
  return r;
}

std::string convergence_table(std::vector<ConvergenceRow> rows, const std::string& csv_path, const std::string& intro) {
  std::sort(rows.begin(), rows.end(), [](const ConvergenceRow& a, const ConvergenceRow& b) {
    return std::tie(a.kind, b.h, b.dt) < std::tie(b.kind, a.h, a.dt);  // by kind, coarse to fine
  });
  for (const ConvergenceRow& r : rows)  // the plot scripts split convergence.csv at commas (awk -F,)
    if (r.kind.find(',') != std::string::npos) throw std::invalid_argument("convergence_table: a kind with a comma breaks the CSV: '" + r.kind + "'");
  std::ofstream csv(csv_path);
  csv << "kind,h_um,dt_s,steps,wall_seconds,error_um,lateral_error_um,failure\n";
  std::ostringstream md;
  md << intro << "\n\n| bodies, coupling | h (um) | Δt (s) | steps | wall (s) | centroid error (um) | x2 error (um) |\n|---|---|---|---|---|---|---|\n";
  for (const ConvergenceRow& r : rows) {
    csv << r.kind << "," << r.h * 1e6 << "," << r.dt << "," << r.steps << "," << r.wall_seconds << "," << r.error * 1e6 << "," << r.x2_error * 1e6
        << "," << (r.failure.empty() ? "" : "stopped") << "\n";
    char line[400];
    if (r.failure.empty())
      std::snprintf(line, sizeof line, "| %s | %g | %.3g | %ld | %.1f | %.2e | %.2e |\n", r.kind.c_str(), r.h * 1e6, r.dt, r.steps, r.wall_seconds,
                    r.error * 1e6, r.x2_error * 1e6);
    else
      std::snprintf(line, sizeof line, "| %s | %g | %.3g | - | - | stopped: %.150s | |\n", r.kind.c_str(), r.h * 1e6, r.dt, r.failure.c_str());
    md << line;
  }
  if (rows.empty()) md << "| (none of its runs finished: a sweep collected before its convergence cases) | | | | | | |\n";
  return md.str();
}

double value_at(const std::vector<double>& t, const std::vector<double>& v, double at) {
  if (t.empty() || at < t.front() || at > t.back()) return NAN;
  const std::size_t k = std::size_t(std::lower_bound(t.begin(), t.end(), at) - t.begin());
  if (t[k] == at || k == 0) return v[k];
  const double f = (at - t[k - 1]) / (t[k] - t[k - 1]);
  return (1 - f) * v[k - 1] + f * v[k];
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
    // A kept run (its folder's code_id: paper/keep_evidence.sh) is read whatever code made it; it
    // names that code (r.code).
    const bool kept = fs::exists(out / "code_id");
    const std::optional<RunSummary> done = o.reuse ? read_finished_run(out.string(), scene, kept) : std::nullopt;
    const std::optional<std::string> stopped = o.reuse && !done ? read_failure() : std::nullopt;
    if (stopped) throw RunFailure(*stopped);
    if (o.collect && !done) {
      r.failure = kNotRun;
      return r;
    }
    fs::remove(failed);
    const bool resume = o.resume && !done && has_checkpoint(out.string());
    if (done) std::getline(std::ifstream(out / "code_id"), r.code);  // a kept run (paper/keep_evidence.sh)
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
