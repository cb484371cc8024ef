#include "single_cell_migration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "io/csv.hpp"

namespace rbc::single_cell_migration {

namespace fs = std::filesystem;

namespace {

const std::vector<double> kFigure3Times = {0.0, 0.05e-3, 0.10e-3, 0.20e-3, 0.30e-3, 0.50e-3, 0.80e-3,
                                           0.90e-3, 1.00e-3, 1.25e-3, 1.50e-3, 2.00e-3, 3.00e-3, 7.50e-3};

std::string tag(double s) {
  char b[16];
  std::snprintf(b, sizeof b, "s%03d", int(std::lround(s * 100)));
  return b;
}

struct Job {
  std::string name;
  Scene scene;
};

Scene channel_scene(double L, double H, double h, double re0, double dt, double end, double every) {
  Scene s;
  s.length = L;
  s.height = H;
  s.mesh_size = h;
  s.reynolds0 = re0;
  s.dt = dt;
  s.end = end;
  s.output_every = every;
  return s;
}

// Figure 3's panels: each snapshot re-centred on its centroid's x1 (the cell travels hundreds
// of um downstream), heights as they are.
void write_centred_snapshots(const fs::path& in_path, const fs::path& out_path) {
  std::ifstream in(in_path);
  std::ofstream out(out_path);
  std::string line;
  std::vector<std::pair<double, double>> pts;
  std::string header;
  auto flush = [&] {
    if (pts.empty()) return;
    double xc = 0;
    for (auto& p : pts) xc += p.first;
    xc /= double(pts.size());
    out << header << "\n";
    for (auto& p : pts) out << (p.first - xc) * 1e6 << " " << p.second * 1e6 << "\n";
    out << "\n\n";
    pts.clear();
  };
  while (std::getline(in, line)) {
    if (line.rfind("# t", 0) == 0) { flush(); header = line; }
    else if (!line.empty() && line[0] != '#') {
      std::stringstream ss(line);
      double x, y;
      ss >> x >> y;
      pts.push_back({x, y});
    }
  }
  flush();
}

double value_at(const std::vector<double>& t, const std::vector<double>& v, double when) {
  std::size_t k = 0;
  while (k + 1 < t.size() && t[k + 1] <= when + 1e-12) ++k;
  return v[k];
}

}  // namespace

Params Params::quick_params() {
  Params p;
  p.quick = true;
  p.narrow_mesh = 0.25e-6;
  p.narrow_dt = 4e-8;
  p.narrow_end = 1e-3;
  p.sample_every = 2e-5;
  p.centreline_check_time = 1e-3;
  return p;
}

Results run(const Params& p) {
  // The cases: the narrow channel under the chosen reading (Figures 3, 4), the other reading over
  // the first millisecond (the units evidence), the wide channel (Figure 5).
  std::vector<Job> jobs;
  for (double s : p.swelling_ratios) {
    Scene sc = channel_scene(20e-6, 10e-6, p.narrow_mesh, 0.5556, p.narrow_dt, p.narrow_end, p.sample_every);
    sc.cells.push_back({{5e-6, 3e-6}, s, 0.0});
    sc.membrane_constants.units = p.units;
    sc.snapshots = kFigure3Times;
    sc.source = "single_cell_migration narrow " + p.units + " s*=" + std::to_string(s);
    jobs.push_back({"narrow_" + p.units + "_" + tag(s), sc});
    if (p.quick) continue;
    if (std::find(p.other_swelling_ratios.begin(), p.other_swelling_ratios.end(), s) != p.other_swelling_ratios.end()) {
    Scene other = sc;
    other.membrane_constants.units = p.other_units;
    other.dt = p.other_dt;
    other.end = p.other_end;
    other.snapshots = {0.0, 0.25e-3, 0.5e-3, 1.0e-3};
    other.source = "single_cell_migration narrow " + p.other_units + " s*=" + std::to_string(s);
    jobs.push_back({"narrow_" + p.other_units + "_" + tag(s), other});
    }
    Scene wide = channel_scene(100e-6, 50e-6, p.wide_mesh, 2.778, p.wide_dt, p.wide_end, p.wide_every);
    wide.cells.push_back({{25e-6, p.wide_y0}, s, 0.0});
    wide.membrane_constants.units = p.units;
    wide.coupling = p.wide_coupling;
    wide.advection_substeps = p.wide_substeps;
    wide.snapshots = {0.0, 0.1, 0.2, 0.4, 0.8};
    char src[160];
    std::snprintf(src, sizeof src, "single_cell_migration wide %s s*=%g %s dt=%g s end=%g s", p.units.c_str(), s,
                  p.wide_coupling.c_str(), p.wide_dt, p.wide_end);
    wide.source = src;
    jobs.push_back({"wide_" + p.units + "_" + tag(s), wide});
  }
  if (!p.only.empty())
    std::erase_if(jobs, [&](const Job& j) { return j.name.rfind(p.only, 0) != 0; });
  // The longest first, two at a time with one thread each (the cases are independent).
  std::stable_sort(jobs.begin(), jobs.end(), [](const Job& a, const Job& b) { return a.scene.end / a.scene.dt > b.scene.end / b.scene.dt; });
  Results res;
  std::mutex lock;
  std::size_t next = 0;
  std::string failure;
  auto worker = [&](int threads) {
    for (;;) {
      Job job;
      {
        std::lock_guard<std::mutex> g(lock);
        if (next >= jobs.size() || !failure.empty()) return;
        job = jobs[next++];
      }
      try {
        const fs::path out = fs::path(p.out_dir) / job.name;
        Case c;
        c.name = job.name;
        c.swelling_ratio = job.scene.cells[0].swelling_ratio;
        c.units = job.scene.membrane_constants.units;
        const std::optional<RunSummary> done = p.reuse ? read_finished_run(out.string(), job.scene) : std::nullopt;
        c.summary = done ? *done : run_scene(job.scene, {out.string(), threads, p.progress, job.name});
        c.t = csv_column((out / "series.csv").string(), "t");
        c.y = csv_column((out / "series.csv").string(), "cell0_y");
        c.hematocrit0 = csv_column((out / "series.csv").string(), "hematocrit").front();
        const double mid = 0.5 * job.scene.height;
        for (std::size_t k = 0; k < c.t.size(); ++k)
          if (std::abs(c.y[k] - mid) < p.centreline_band) { c.time_to_centreline = c.t[k]; break; }
        if (fs::exists(out / "snapshots.dat")) write_centred_snapshots(out / "snapshots.dat", out / "snapshots_centred.dat");
        std::lock_guard<std::mutex> g(lock);
        res.cases[job.name] = c;
      } catch (const RunFailure& e) {
        // An unstable case is reported, not hidden: its rows fail with the cause.
        Case c;
        c.name = job.name;
        c.swelling_ratio = job.scene.cells[0].swelling_ratio;
        c.units = job.scene.membrane_constants.units;
        c.failure = e.what();
        std::lock_guard<std::mutex> g(lock);
        res.cases[job.name] = c;
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> g(lock);
        failure = job.name + ": " + e.what();
      }
    }
  };
  if (p.threads > 0) worker(p.threads);
  else {
    std::thread a(worker, 1), b(worker, 1);
    a.join();
    b.join();
  }
  if (!failure.empty()) throw RunFailure(failure);
  if (!p.only.empty()) return res;  // a part: no comparison with the study

  // The study's rows (reference-data/single_cell_migration.csv).
  auto narrow = [&](double s) -> const Case& { return res.cases.at("narrow_" + p.units + "_" + tag(s)); };
  const std::map<double, std::string> ids = {{0.55, "s055"}, {0.7, "s07"}, {1.0, "s10"}};
  for (double s : p.swelling_ratios) {
    if (!ids.count(s)) continue;
    const Case& c = narrow(s);
    const std::string id = ids.at(s);
    if (!c.failure.empty()) {
      for (const char* row : {"hct_", "re_", "centreline_"}) res.measured[std::string(row) + id] = {{}, false, "run failed: " + c.failure};
      continue;
    }
    res.measured["hct_" + id] = {c.summary.hematocrit, {}, "end of run; " + std::to_string(c.hematocrit0).substr(0, 6) + " % at t = 0"};
    if (!p.quick) {
      res.measured["re_" + id] = {c.summary.reynolds, {}, ""};
      const double y7 = value_at(c.t, c.y, p.centreline_check_time);
      char note[64];
      std::snprintf(note, sizeof note, "y(%.1f ms) = %.3f um", p.centreline_check_time * 1e3, y7 * 1e6);
      res.measured["centreline_" + id] = {{}, std::abs(y7 - 5e-6) < p.centreline_band, note};
      const std::string kind = c.summary.cells[0].shape.kind;
      if (id != "s10") res.measured["parachute_" + id] = {{}, kind == "parachute", "shape at 7.5 ms: " + kind};
      else res.measured["bullet_s10"] = {{}, kind == "bullet", "shape at 7.5 ms: " + kind};
    }
  }
  bool all_ran = true;
  for (const auto& [name, c] : res.cases) all_ran = all_ran && c.failure.empty();
  if (!p.quick && ids.size() == p.swelling_ratios.size() && all_ran) {
    // s* = 1 slowest: its time to reach the centreline band is the largest.
    auto ttc = [&](double s) { const double t = narrow(s).time_to_centreline; return t < 0 ? INFINITY : t; };
    char note[96];
    std::snprintf(note, sizeof note, "times to centreline %.2f, %.2f, %.2f ms", ttc(0.55) * 1e3, ttc(0.7) * 1e3, ttc(1.0) * 1e3);
    res.measured["slowest_s10"] = {{}, ttc(1.0) > ttc(0.55) && ttc(1.0) > ttc(0.7), note};
    // Wide channel: at the end of what ran, the smaller s* is closer to the centreline.
    auto wide_y = [&](double s) { return res.cases.at("wide_" + p.units + "_" + tag(s)).y.back(); };
    std::snprintf(note, sizeof note, "y(%.0f ms) = %.2f, %.2f, %.2f um", p.wide_end * 1e3, wide_y(0.55) * 1e6, wide_y(0.7) * 1e6, wide_y(1.0) * 1e6);
    res.measured["wide_ordering"] = {{}, wide_y(0.55) > wide_y(0.7) && wide_y(0.7) > wide_y(1.0), note};
    // The units evidence, side by side at the end of the other reading's run.
    std::ostringstream ev;
    ev << "| s* | reading | y at " << p.other_end * 1e3 << " ms (um) | shape at " << p.other_end * 1e3
       << " ms | rear concavity |\n|---|---|---|---|---|\n";
    for (double s : p.other_swelling_ratios)
      for (const std::string& u : {p.units, p.other_units}) {
        const Case& c = res.cases.at("narrow_" + u + "_" + tag(s));
        // The chosen reading ran longer: read its state at the other's end from the snapshots'
        // run; the height from the series, the shape from the summary of the shorter run only.
        const double y = value_at(c.t, c.y, p.other_end);
        std::string shape = "(see Fig. 3)";
        double kr = NAN;
        if (u == p.other_units) { shape = c.summary.cells[0].shape.kind; kr = c.summary.cells[0].shape.rear_concavity; }
        char row[160];
        std::snprintf(row, sizeof row, "| %.2f | %s | %.3f | %s | %s |\n", s, u.c_str(), y * 1e6, shape.c_str(),
                      std::isnan(kr) ? "" : std::to_string(kr).substr(0, 5).c_str());
        ev << row;
      }
    res.units_evidence = ev.str();
  }
  return res;
}

}  // namespace rbc::single_cell_migration
