#include "cell_free_layer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include <nlohmann/json.hpp>

#include "common/case_runner.hpp"
#include "io/csv.hpp"
#include "reference/uncertainty.hpp"

namespace rbc::cell_free_layer {

namespace fs = std::filesystem;
using case_runner::num;

namespace {

const std::string kSceneFile = std::string(RBCFLOW_SOURCE_DIR) + "/experiments/cell_free_layer/cell_free_layer.toml";

// "n50", "n100": a case's base name (appended, not "n" + ..., which GCC 12 warns about falsely).
std::string base_name(int cells) {
  std::string s = "n";
  s += std::to_string(cells);
  return s;
}

// The study's end times: 150 ms for 50 cells, 200 ms for 100 (Figs. 9-10).
double study_end(int cells) { return cells == 50 ? 0.15 : 0.2; }

// The study's snapshot times (Fig. 9: 0, 50, 100, 150 ms; Fig. 10: 0, 100, 150, 200 ms) and those
// of the Hct profile (every kProfileEvery over the last kProfileWindow).
std::vector<double> snapshot_times(int cells, double end, bool quick) {
  std::vector<double> t = {0.0};
  if (!quick) {
    if (cells == 50) t.insert(t.end(), {0.05, 0.1});
    else t.insert(t.end(), {0.1, 0.15});
  }
  const double window = quick ? end / 2 : kProfileWindow, every = quick ? end / 10 : kProfileEvery;
  const int n = int(std::lround(window / every));
  for (int k = n; k >= 0; --k)
    if (end - k * every > 0) t.push_back(end - k * every);  // (a run shorter than the window: from its start)
  std::sort(t.begin(), t.end());
  t.erase(std::unique(t.begin(), t.end(), [](double a, double b) { return std::abs(a - b) < 1e-12; }), t.end());
  return t;
}

// The length of the line x2 = y inside the closed polygon r (the sum of its inside intervals).
double chord(const std::vector<Eigen::Vector2d>& r, double y) {
  std::vector<double> xs;
  for (std::size_t i = 0, n = r.size(), j = n - 1; i < n; j = i++)
    if ((r[i].y() > y) != (r[j].y() > y)) xs.push_back(r[j].x() + (y - r[j].y()) * (r[i].x() - r[j].x()) / (r[i].y() - r[j].y()));
  std::sort(xs.begin(), xs.end());
  double c = 0;
  for (std::size_t k = 0; k + 1 < xs.size(); k += 2) c += xs[k + 1] - xs[k];
  return c;
}

}  // namespace

std::vector<Eigen::Vector2d> arrangement(int n, unsigned seed, double L, double H, double margin) {
  if (n <= 0 || n % kColumns != 0) throw std::invalid_argument("cell_free_layer: the lattice needs a multiple of " + std::to_string(kColumns) + " cells");
  const int rows = n / kColumns;
  std::mt19937 g(seed);
  std::vector<Eigen::Vector2d> c;
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < kColumns; ++k) {
      Eigen::Vector2d p((k + 0.5 + (r % 2 ? 0.5 : 0.0)) * L / kColumns, margin + (r + 0.5) * (H - 2 * margin) / rows);
      if (seed != 0) {
        p.x() += kShiftX * case_runner::symmetric_unit(g);
        p.y() += shift_y(rows, H) * case_runner::symmetric_unit(g);
      }
      c.push_back(p);
    }
  return c;
}

Scene case_scene(const Case& c, bool quick) {
  std::ifstream in(kSceneFile);
  if (!in) throw std::runtime_error("cell_free_layer: cannot read " + kSceneFile);
  std::ostringstream text;
  text << in.rdbuf() << "\n";
  const Scene channel = parse_scene(text.str(), kSceneFile);
  for (const auto& at : arrangement(c.cells, c.seed, channel.length, channel.height, c.margin))
    text << "[[cell]]\ncenter = [" << num(at.x()) << ", " << num(at.y()) << "]\nswelling_ratio = " << num(kSwellingRatio) << "\n";
  std::vector<std::string> o;
  const double h = c.h > 0 ? c.h : quick ? kQuickMesh : 0;
  if (h > 0) o.push_back("channel.mesh_size=" + num(h));
  const double end = c.end > 0 ? c.end : quick ? kQuickEnd : study_end(c.cells);
  o.push_back("time.end=" + num(end));
  std::string snaps = "output.snapshots=[";
  for (double t : snapshot_times(c.cells, end, quick)) snaps += num(t) + ",";
  snaps.back() = ']';
  o.push_back(snaps);
  if (c.dt > 0) {
    const int q = parse_scene(text.str(), kSceneFile, o).advection_substeps_for(c.dt);
    o.push_back("time.dt=" + num(c.dt));
    o.push_back("time.advection_substeps=" + std::to_string(q));
  }
  if (!c.coupling.empty()) o.push_back("time.coupling=\"" + c.coupling + "\"");
  if (!c.projection.empty()) o.push_back("time.projection=\"" + c.projection + "\"");
  if (!c.scheme.empty()) o.push_back("time.scheme=\"" + c.scheme + "\"");
  if (c.repulsion > 0) {
    const double mesh = h > 0 ? h : channel.mesh_size;
    o.push_back("repulsion.range=" + num(kRepulsionRangeCells * mesh));
    o.push_back("repulsion.strength=" + num(c.repulsion));
  }
  Scene s = parse_scene(text.str(), kSceneFile, o);
  s.source = "cell_free_layer " + c.name + (quick ? " quick" : "");
  return s;
}

std::string form_case_name(const std::string& projection, double dt) {
  char b[64];
  std::snprintf(b, sizeof b, "n100_early_%s_dt%gus", projection == "study" ? "study" : "inc", dt * 1e6);
  return b;
}

namespace {

// The layer (mean of the walls' gaps) at each sample of a run, um.
std::vector<double> layer_series_um(const CaseResult& c) {
  std::vector<double> v(c.t.size());
  for (std::size_t k = 0; k < c.t.size(); ++k) v[k] = 0.5 * (c.gap_lower[k] + c.gap_upper[k]) * 1e6;
  return v;
}

}  // namespace

std::vector<Case> cases(const Params& p) {
  std::vector<Case> v;
  auto make = [](std::string name, std::string role, int n, unsigned seed) {
    Case c;
    c.name = std::move(name);
    c.role = std::move(role);
    c.cells = n;
    c.seed = seed;
    c.repulsion = n == 100 ? kRepulsionStrength : 0.0;  // the crowded cases only (the .hpp says why)
    return c;
  };
  // The longest first (GNU parallel starts them in this order): Δt halved, the study's form of the
  // pressure (the cause of the deviation the experiment had in it: README.md, Deviations), then
  // 100 cells, 50.
  if ((p.evidence || p.study_only) && !p.quick) {
    for (int n : {100, 50}) {
      Case c = make(base_name(n) + "_dt1.5us", "evidence", n, 1);
      c.dt = 1.5e-6;
      c.reported = true;  // the rows report the finest Δt (run())
      v.push_back(c);
    }
  }
  if ((p.evidence || p.study_only) && !p.quick) {
    // The arrangements at the rows' Δt: the ensemble the rows are judged by (make evidence runs
    // them; make reproduce reads those finished or kept, and runs seed 1 alone).
    for (int n : {100, 50})
      for (unsigned s : p.seeds) {
        Case c = make(base_name(n) + "_dt1.5us_seed" + std::to_string(s), "ensemble_reported", n, s);
        c.dt = 1.5e-6;
        v.push_back(c);
      }
  }
  if (p.evidence && !p.quick) {
    for (int n : {100, 50}) {  // the study's pressure splitting at our step (README.md, Deviations)
      Case c = make(base_name(n) + "_study_pressure", "evidence", n, 1);
      c.projection = "study";
      v.push_back(c);
      if (n == 100) {
        c.name = base_name(n) + "_study_pressure_dt1.5us";  // its Δt error
        c.dt = 1.5e-6;
        v.push_back(c);
      }
    }
    // The study's form of the pressure against the incremental one over a Δt ladder to kEarlyEnd.
    for (double dt : kFormDts)
      for (const char* form : {"study", "incremental"}) {
        Case c = make(form_case_name(form, dt), "form", 100, 1);
        c.projection = form;
        c.dt = dt;
        c.end = kEarlyEnd;
        v.push_back(c);
      }
    Case bare = make(base_name(100) + "_no_repulsion", "evidence", 100, 1);  // does the crowd still need it?
    bare.repulsion = 0;
    v.push_back(bare);
  }
  for (int n : {100, 50}) {
    v.push_back(make(base_name(n), "study", n, 1));
    if (!p.quick)
      for (unsigned s : p.seeds) v.push_back(make(base_name(n) + "_seed" + std::to_string(s), "ensemble", n, s));
    if (n == 100 && p.evidence && !p.quick) {
      Case wide = make(base_name(n) + "_wide_gaps", "evidence", n, 1);  // the start's effect on the layer
      wide.margin = kWideGapMargin;
      v.push_back(wide);
      Case early = make(base_name(n) + "_explicit_early", "evidence", n, 1);  // the study's scheme, Δt → 0
      early.coupling = "explicit";
      early.projection = "study";
      early.dt = kExplicitDt;
      early.end = kEarlyEnd;
      v.push_back(early);
    }
  }
  if (p.evidence && !p.quick) {
    for (int n : {100, 50}) {
      Case c = make(base_name(n) + "_h0.625um", "evidence", n, 1);
      c.h = 0.625e-6;
      v.push_back(c);
    }
    Case c = make("n50_repulsion", "evidence", 50, 1);  // the repulsion's effect on the rows
    c.repulsion = kRepulsionStrength;
    v.push_back(c);
  }
  if (p.convergence && !p.quick) {
    // Explicit below its stability limit (6e-8 s for 100 cells at h = 0.3125 um: bench_channel),
    // the semi-implicit coupling from twice the experiment's Δt down, at h = 0.3125 um down to the
    // explicit run's own Δt (the two couplings must then agree: the early-layer table); the
    // longest first. The study's own scheme (explicit, the study's form of the pressure) is the
    // reference; the semi-implicit runs in both forms of the pressure: "_inc" in the name, the
    // experiment's (README.md, Deviations), and without it the study's form; "sie": the
    // semi-implicit coupling in the extrapolated Lie scheme (incremental form: its second-order
    // form, paper/method/07_second_order_in_time.md). kind: case_runner's.
    struct Job { std::string kind; double h; std::vector<double> dts; bool incremental = false; };
    const Job jobs[] = {{"explicit", 0.3125e-6, {2.5e-8, 5e-8}},
                        {"explicit", 0.625e-6, {5e-8, 1e-7}},
                        {"explicit", 0.3125e-6, {5e-8}, true},
                        {"semi-implicit", 0.3125e-6, {5e-8, 2e-7, 7.5e-7, 1.5e-6, 3e-6, 6e-6}},
                        {"semi-implicit", 0.3125e-6, {7.5e-7, 1.5e-6, 3e-6, 6e-6}, true},
                        {"semi-implicit", 0.625e-6, {7.5e-7, 1.5e-6, 3e-6, 6e-6}, true},
                        {case_runner::kExtrapolatedKind, 0.3125e-6, {1.5e-6, 3e-6, 6e-6}, true},
                        {case_runner::kExtrapolatedKind, 0.625e-6, {1.5e-6, 3e-6, 6e-6}, true}};
    for (const Job& j : jobs)
      for (double dt : j.dts) {
        char name[96];
        std::snprintf(name, sizeof name, "conv_%s%s_h%g_dt%g",
                      case_runner::short_kind(j.kind).c_str(), j.incremental ? "_inc" : "", j.h * 1e6, dt);
        Case c = make(name, "convergence", 50, 1);
        c.coupling = case_runner::coupling_of(j.kind);
        c.projection = j.incremental ? "incremental" : "study";
        if (j.kind == case_runner::kExtrapolatedKind) c.scheme = case_runner::scheme_of(j.kind);
        c.h = j.h;
        c.dt = dt;
        c.end = (std::round(kConvTime / dt) - 0.5) * dt;  // the run stops at the first step at or past end: step N
        v.push_back(c);
      }
  }
  if (p.quick) for (Case& c : v) c.reported = c.role == "study";
  if (p.study_only && !p.quick) {
    // make reproduce runs the reported runs alone; the arrangements the rows are judged by (at
    // 1.5 us) and paired with (at 3 us) are read where finished or kept, never run.
    for (Case& c : v)
      if (!c.reported && (c.role == "ensemble_reported" || c.role == "ensemble" || c.role == "study")) c.read_only = true;
    std::erase_if(v, [](const Case& c) { return !c.reported && !c.read_only && !case_runner::in_report_convergence(c.role, c.h); });
  }
  return v;
}

void hematocrit_profile(const std::string& snapshots, double from, double L, double H, double dy, std::vector<double>& y,
                        std::vector<double>& fraction) {
  const int bins = int(std::lround(H / dy));
  y.assign(bins, 0.0);
  fraction.assign(bins, 0.0);
  for (int b = 0; b < bins; ++b) y[b] = (b + 0.5) * H / bins;
  std::ifstream f(snapshots);
  if (!f) throw std::runtime_error("cell_free_layer: cannot read " + snapshots);
  std::string line;
  double t = -1;
  int used = 0;
  std::vector<Eigen::Vector2d> cell;
  auto finish_cell = [&] {
    if (t >= from - 1e-12 && cell.size() > 2)
      for (int b = 0; b < bins; ++b) fraction[b] += chord(cell, y[b]) / L;
    cell.clear();
  };
  while (std::getline(f, line)) {
    if (line.rfind("# t = ", 0) == 0) {
      finish_cell();
      t = std::stod(line.substr(6));
      if (t >= from - 1e-12) ++used;
    } else if (line.rfind("# cell", 0) == 0 || line.empty()) {
      finish_cell();
    } else {
      double x1, x2;
      if (std::sscanf(line.c_str(), "%lf %lf", &x1, &x2) == 2) cell.emplace_back(x1, x2);
    }
  }
  finish_cell();
  if (used == 0) throw std::runtime_error("cell_free_layer: no snapshot at or after t = " + std::to_string(from) + " s in " + snapshots);
  for (double& v : fraction) v /= used;
}

namespace {

CaseResult run_case(const Params& p, const Case& c) {
  CaseResult r;
  r.spec = c;
  const Scene scene = case_scene(c, p.quick);
  r.h = scene.mesh_size;
  r.dt = scene.dt;
  r.length = scene.length;
  const fs::path out = fs::path(p.out_dir) / c.name;
  const case_runner::CaseRun run = case_runner::run_or_reuse(
      scene, out.string(),
      {.threads = p.threads, .progress = p.progress, .resume = p.resume, .reuse = p.reuse || p.collect || c.read_only, .collect = p.collect || c.read_only,
       .label = "cell_free_layer " + c.name});
  r.summary = run.summary;
  r.failure = run.failure;
  r.code = run.code;
  if (r.failure == case_runner::kNotRun) return r;
  const std::string series = (out / "series.csv").string();
  if (!fs::exists(series)) {
    if (r.failure.empty()) r.failure = "no series.csv in " + out.string();
    return r;
  }
  if (c.repulsion > 0 && fs::exists(out / "summary.json")) {
    std::ifstream js(out / "summary.json");
    r.repulsion_steps = nlohmann::json::parse(js).value("membrane_repulsion_steps", 0L);
  }
  r.t = csv_column(series, "t");
  for (int k = 0; k < c.cells && c.role == "convergence"; ++k) {  // the error-against-run-time table's
    const std::vector<double> x = csv_column(series, "cell" + std::to_string(k) + "_x"), y = csv_column(series, "cell" + std::to_string(k) + "_y");
    r.centroids_end.emplace_back(x.back(), y.back());
  }
  r.gap_lower = csv_column(series, "wall_gap_lower");
  r.gap_upper = csv_column(series, "wall_gap_upper");
  r.hematocrit = csv_column(series, "hematocrit");
  r.reynolds = csv_column(series, "reynolds");
  if (!r.failure.empty() || r.t.empty()) return r;
  const double from = r.t.back() - kWindow;
  r.layer_lower = case_runner::window_mean(r.t, r.gap_lower, from);
  r.layer_upper = case_runner::window_mean(r.t, r.gap_upper, from);
  r.layer = 0.5 * (r.layer_lower + r.layer_upper);
  r.layer_late = 0.5 * (case_runner::window_mean(r.t, r.gap_lower, r.t.back() / 2) + case_runner::window_mean(r.t, r.gap_upper, r.t.back() / 2));
  r.hct = case_runner::window_mean(r.t, r.hematocrit, from);
  r.re = case_runner::window_mean(r.t, r.reynolds, from);
  const double window = p.quick ? r.t.back() / 2 : kProfileWindow;
  if (fs::exists(out / "snapshots.dat"))  // (a kept run keeps none: paper/keep_evidence.sh)
    hematocrit_profile((out / "snapshots.dat").string(), r.t.back() - window, scene.length, scene.height, scene.mesh_size, r.profile_y, r.profile);
  // The layer against time (Figs. 9-10's companion) and the profile, for plot.gp.
  std::ofstream f(fs::path(p.out_dir) / ("layer_" + c.name + ".dat"));
  f << "# " << c.cells << " cells s* = 0.7, arrangement seed " << c.seed << "\n# t (ms), gap lower wall (um), gap upper wall (um), mean (um), Hct (%), Re\n";
  for (std::size_t k = 0; k < r.t.size(); ++k)
    f << r.t[k] * 1e3 << " " << r.gap_lower[k] * 1e6 << " " << r.gap_upper[k] * 1e6 << " " << 0.5 * (r.gap_lower[k] + r.gap_upper[k]) * 1e6 << " "
      << r.hematocrit[k] << " " << r.reynolds[k] << "\n";
  std::ofstream g(fs::path(p.out_dir) / ("profile_" + c.name + ".dat"));
  g << "# area fraction of cells (%) across the channel, mean over the snapshots of the last " << window * 1e3 << " ms\n# x2 (um), Hct(x2) (%)\n";
  for (std::size_t b = 0; b < r.profile.size(); ++b) g << r.profile_y[b] * 1e6 << " " << 100 * r.profile[b] << "\n";
  return r;
}

double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); }

// A table cell: x in the printf format, "-" for NaN (the run is missing or stopped).
std::string shown(double x, const char* format) {
  char b[40];
  if (std::isnan(x)) return "-";
  std::snprintf(b, sizeof b, format, x);
  return b;
}

}  // namespace

// Every row's value over the arrangements (the study's seed and the ensemble's), their mean and
// sample standard deviation, and the change with Δt halved, with the study's pressure form and with h doubled.
std::string ensemble_table(const Params& p, const Results& res) {
  auto ok = [&](const std::string& n) { return res.cases.count(n) && res.cases.at(n).failure.empty(); };
  std::ostringstream md;
  md << "Rows over the arrangements (seed 1: the study's case; the others: the ensemble), their mean and sample standard deviation s, "
        "(the layer also over the run's second half, a steadier measure than the study's last millisecond), and the change of the study's case with Δt halved, with the study's form of the pressure splitting in place of the incremental one (README.md, Deviations), (100 cells) started about 2.9 um off the walls, with h doubled, and what the membrane repulsion does: (50 cells) the 100-cell cases' repulsion "
        "switched on, (100 cells) seed 1 less its run without the repulsion (the rows' u_num is made from s, the Δt/2 change and the window noise; their tolerances come from the study alone: "
        "reference-data/README.md):\n\n"
        "| row | seed 1 | other seeds | mean | s | Δt/2 − seed 1 | study's p − seed 1 | wide gaps − seed 1 | 2h − seed 1 | the repulsion's effect |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n";
  struct Q { const char* label; double CaseResult::*field; double scale; };
  const Q qs[] = {{"cell-free layer, mean of the walls (um)", &CaseResult::layer, 1e6},
                  {"cell-free layer, lower wall (um)", &CaseResult::layer_lower, 1e6},
                  {"cell-free layer, upper wall (um)", &CaseResult::layer_upper, 1e6},
                  {"cell-free layer, mean of the walls over the run's second half (um; not a row)", &CaseResult::layer_late, 1e6},
                  {"Re", &CaseResult::re, 1.0},
                  {"Hct (%)", &CaseResult::hct, 1.0}};
  for (int n : {50, 100}) {
    const std::string base = base_name(n);
    if (!ok(base)) continue;
    for (const Q& q : qs) {
      std::vector<double> v = {res.cases.at(base).*q.field * q.scale};
      std::string others;
      for (unsigned s : p.seeds) {
        const std::string name = base + "_seed" + std::to_string(s);
        char b[40];
        if (ok(name)) {
          v.push_back(res.cases.at(name).*q.field * q.scale);
          std::snprintf(b, sizeof b, " %.4g", v.back());
        } else {
          std::snprintf(b, sizeof b, " (seed %u: %s)", s, res.cases.count(name) ? "stopped" : "not run");
        }
        others += b;
      }
      auto change = [&](const std::string& name) { return ok(name) ? res.cases.at(name).*q.field * q.scale - v[0] : NAN; };
      char row[700];
      std::snprintf(row, sizeof row, "| %d cells: %s | %.4g |%s | %.4g | %s | %s | %s | %s | %s | %s |\n", n, q.label, v[0], others.c_str(),
                    mean(v), shown(sample_std(v), "%.3g").c_str(), shown(change(base + "_dt1.5us"), "%+.3g").c_str(),
                    shown(change(base + "_study_pressure"), "%+.3g").c_str(),
                    shown(change(base + "_wide_gaps"), "%+.3g").c_str(),
                    shown(change(base + "_h0.625um"), "%+.3g").c_str(),
                    shown(ok(base + "_no_repulsion") ? -change(base + "_no_repulsion") : change(base + "_repulsion"), "%+.3g").c_str());
      md << row;
    }
  }
  return md.str();
}

// The study's form of the pressure against the incremental one with 100 cells over the Δt ladder
// kFormDts to kEarlyEnd, and the study's own scheme (n100_explicit_early) beside them: the layer
// and Re, each the mean over [kEarlyFrom, kEarlyEnd] (Re also over the last ms, the rows'
// window, which the crowd's fluctuation dominates), their difference at each Δt, and each form's
// Δt -> 0 limit by the least-squares estimator (its consecutive finished levels, at least three,
// first order): does the study's form
// converge to the other's answer, and both to the study's scheme's?
std::string form_table(const Results& res) {
  auto ok = [&](const std::string& n) { return res.cases.count(n) && res.cases.at(n).failure.empty(); };
  auto layer = [&](const CaseResult& c) { return case_runner::window_mean(c.t, layer_series_um(c), kEarlyFrom); };
  auto re_mean = [&](const CaseResult& c) { return case_runner::window_mean(c.t, c.reynolds, kEarlyFrom); };
  std::ostringstream md;
  bool any = false;
  std::map<std::string, std::vector<double>> layers, res_;
  std::map<std::string, bool> gap;  // a level missing after the form's finest finished one
  for (double dt : kFormDts) {
    const std::string a = form_case_name("study", dt), b = form_case_name("incremental", dt);
    const double la = ok(a) ? layer(res.cases.at(a)) : NAN, lb = ok(b) ? layer(res.cases.at(b)) : NAN;
    const double ra = ok(a) ? re_mean(res.cases.at(a)) : NAN, rb = ok(b) ? re_mean(res.cases.at(b)) : NAN;
    // Each form's levels for its limit: consecutive ones from its finest finished level (ratio 2),
    // so a level missing after it closes the form's sequence (also when both forms miss it).
    for (const auto& [form, done, l, r] : {std::tuple{"study", ok(a), la, ra}, std::tuple{"inc", ok(b), lb, rb}}) {
      if (done && !gap[form]) {
        layers[form].push_back(l);
        res_[form].push_back(r);
      } else if (!done && !layers[form].empty()) {
        gap[form] = true;
      }
    }
    if (!ok(a) && !ok(b)) continue;
    if (!any)
      md << "\nThe study's form of the pressure against the incremental form (100 cells, seed 1, h = 0.3125 um, from rest to " << kEarlyEnd * 1e3
         << " ms): the layer (mean of the walls, um) and Re, each the mean over " << kEarlyFrom * 1e3 << "-" << kEarlyEnd * 1e3
         << " ms; and the difference of Re over the last ms alone (the rows' window, where the crowd's fluctuation dominates):\n\n"
            "| dt (us) | layer, study's p | layer, incremental p | study − incremental | Re, study's p | Re, incremental p | study − incremental | "
            "study − incremental, Re over the last ms |\n|---|---|---|---|---|---|---|---|\n";
    any = true;
    const double last = ok(a) && ok(b) ? res.cases.at(a).re - res.cases.at(b).re : NAN;
    char row[400];
    std::snprintf(row, sizeof row, "| %g | %s | %s | %s | %s | %s | %s | %s |\n", dt * 1e6, shown(la, "%.3f").c_str(), shown(lb, "%.3f").c_str(),
                  shown(la - lb, "%+.3f").c_str(), shown(ra, "%.4f").c_str(), shown(rb, "%.4f").c_str(), shown(ra - rb, "%+.4f").c_str(),
                  shown(last, "%+.4f").c_str());
    md << row;
  }
  if (!any) return "";
  if (ok("n100_explicit_early")) {
    const CaseResult& e = res.cases.at("n100_explicit_early");
    char row[200];
    std::snprintf(row, sizeof row, "| explicit, %g (the study's scheme) | %.3f | | | %.4f | | | |\n", kExplicitDt * 1e6, layer(e), re_mean(e));
    md << row;
  }
  // The incremental form's levels barely move with Δt: their spread is the size of a difference
  // these single chaotic runs resolve.
  for (const auto& [what, by_form] : {std::pair{"layer (um)", &layers}, std::pair{"Re", &res_}})
    if (const auto in = by_form->find("inc"); in != by_form->end() && in->second.size() >= 2) {
      char line[300];
      std::snprintf(line, sizeof line, "\n%s: the incremental form's levels scatter by s = %.2g (the size of a difference one run resolves).\n", what,
                    sample_std(in->second));
      md << line;
    }
  // Each form's limit over its consecutive finished levels, at least three (finest first, ratio 2,
  // formal order 1).
  for (const auto& [what, by_form] : {std::pair{"layer (um)", &layers}, std::pair{"Re", &res_}}) {
    const auto& st = by_form->find("study"), & in = by_form->find("inc");
    if (st == by_form->end() || in == by_form->end() || st->second.size() < 3 || in->second.size() < 3) continue;
    const RefinementUncertainty us = grid_convergence_index(st->second, 2.0, 1.0), ui = grid_convergence_index(in->second, 2.0, 1.0);
    const double gap = us.extrapolated - ui.extrapolated, reach = std::hypot(us.u, ui.u);
    char line[500];
    std::snprintf(line, sizeof line,
                  "\n%s as dt -> 0: the study's form %.4g (U %.2g; %s), the incremental form %.4g (U %.2g; %s): they differ by %+.3g, %s "
                  "(%.2g); the difference at the finest dt %+.3g, at the coarsest %+.3g.\n",
                  what, us.extrapolated, us.u, us.describe(2).c_str(), ui.extrapolated, ui.u, ui.describe(2).c_str(), gap,
                  std::abs(gap) <= reach ? "within their combined U: consistent with one answer for both forms"
                                         : "beyond their combined U: the two forms do not reach one answer at these dt",
                  reach, st->second.front() - in->second.front(), st->second.back() - in->second.back());
    md << line;
    if (ok("n100_explicit_early")) {  // the study's own scheme: the answer both should reach
      const CaseResult& e = res.cases.at("n100_explicit_early");
      const double ref = what == std::string("Re") ? re_mean(e) : layer(e);
      std::snprintf(line, sizeof line,
                    "The study's scheme (n100_explicit_early) %.4g: the study's form's limit %+.3g from it (U %.2g), the incremental "
                    "form's %+.3g (U %.2g); the finest runs %+.3g and %+.3g.\n",
                    ref, us.extrapolated - ref, us.u, ui.extrapolated - ref, ui.u, st->second.front() - ref, in->second.front() - ref);
      md << line;
    }
  }
  return md.str();
}

std::string early_layer_table(const Results& res) {
  // The mean of the two walls' gaps over the samples in [from, to] (every run has them from t = 0,
  // whatever its end); NaN if the run stopped or ended before `to`.
  auto window = [&](const std::string& name, double from, double to) {
    const auto it = res.cases.find(name);
    if (it == res.cases.end() || !it->second.failure.empty() || it->second.t.empty() || it->second.t.back() < to - 1e-9) return double(NAN);
    const CaseResult& c = it->second;
    double sum = 0;
    int n = 0;
    for (std::size_t k = 0; k < c.t.size(); ++k)
      if (c.t[k] >= from - 1e-12 && c.t[k] <= to + 1e-12) {
        sum += 0.5 * (c.gap_lower[k] + c.gap_upper[k]);
        ++n;
      }
    return n ? sum / n : double(NAN);
  };
  struct Row { const char* name; int cells; const char* coupling; const char* dt; };
  const Row rows[] = {{"conv_explicit_h0.3125_dt2.5e-08", 50, "explicit, study's p (the study's scheme)", "0.025"},
                      {"conv_explicit_h0.3125_dt5e-08", 50, "explicit, study's p (the study's scheme)", "0.05"},
                      {"conv_explicit_inc_h0.3125_dt5e-08", 50, "explicit, incremental p", "0.05"},
                      {"conv_si_h0.3125_dt5e-08", 50, "semi-implicit, study's p", "0.05"},
                      {"conv_si_h0.3125_dt2e-07", 50, "semi-implicit, study's p", "0.2"},
                      {"conv_si_h0.3125_dt7.5e-07", 50, "semi-implicit, study's p", "0.75"},
                      {"conv_si_h0.3125_dt1.5e-06", 50, "semi-implicit, study's p", "1.5"},
                      {"conv_si_h0.3125_dt3e-06", 50, "semi-implicit, study's p", "3"},
                      {"conv_si_h0.3125_dt6e-06", 50, "semi-implicit, study's p", "6"},
                      {"conv_si_inc_h0.3125_dt7.5e-07", 50, "semi-implicit, incremental p", "0.75"},
                      {"conv_si_inc_h0.3125_dt1.5e-06", 50, "semi-implicit, incremental p", "1.5"},
                      {"conv_si_inc_h0.3125_dt3e-06", 50, "semi-implicit, incremental p (the experiment's)", "3"},
                      {"conv_si_inc_h0.3125_dt6e-06", 50, "semi-implicit, incremental p", "6"},
                      {"n100_explicit_early", 100, "explicit, study's p (the study's scheme)", "0.05"},
                      {"n100_study_pressure_dt1.5us", 100, "semi-implicit, study's p", "1.5"},
                      {"n100_study_pressure", 100, "semi-implicit, study's p", "3"},
                      {"n100_dt1.5us", 100, "semi-implicit, incremental p", "1.5"},
                      {"n100", 100, "semi-implicit, incremental p (the study's case)", "3"},
                      {"n100_no_repulsion", 100, "semi-implicit, incremental p, no repulsion", "3"}};
  std::ostringstream md;
  bool any = false;
  for (const Row& r : rows) {
    const double first = window(r.name, kConvTime / 2, kConvTime), second = r.cells == 100 ? window(r.name, kEarlyFrom, kEarlyEnd) : NAN;
    if (std::isnan(first) && std::isnan(second)) continue;
    if (!any)
      md << "\nThe early layer against the coupling and the time step (seed 1, h = 0.3125 um, the same start; the mean of the walls over the "
            "samples every 0.1 ms in each window, um; 50 cells: the 1.2 ms runs of the error-against-run-time study):\n\n"
            "| cells | coupling | dt (us) | layer " << kConvTime / 2 * 1e3 << "-" << kConvTime * 1e3 << " ms | layer " << kEarlyFrom * 1e3 << "-"
         << kEarlyEnd * 1e3 << " ms |\n|---|---|---|---|---|\n";
    any = true;
    md << "| " << r.cells << " | " << r.coupling << " | " << r.dt << " | " << shown(first * 1e6, "%.3f") << " | " << shown(second * 1e6, "%.3f")
       << " |\n";
  }
  return any ? md.str() : std::string();
}

namespace {

// The work-precision table: RMS centroid error of the 50 cells at kConvTime against the explicit
// run (the study's form of the pressure) at the finest h present and its smallest Δt (make evidence:
// h = 0.3125 um; make reproduce: the coarse ladder, case_runner.hpp), and each run's wall time.
std::string convergence_table(const Params& p, const Results& res) {
  const CaseResult* ref = nullptr;
  for (const auto& [name, r] : res.cases)
    if (r.spec.role == "convergence" && r.failure.empty() && r.spec.coupling == "explicit" && r.spec.projection == "study" &&
        (!ref || r.h < ref->h || (r.h == ref->h && r.dt < ref->dt)))
      ref = &r;
  if (!ref) return "";
  std::vector<case_runner::ConvergenceRow> rows;
  for (const auto& [name, r] : res.cases) {
    if (r.spec.role != "convergence") continue;
    case_runner::ConvergenceRow row{.kind = case_runner::kind_of(r.spec.coupling, r.spec.scheme) +
                                            (r.spec.projection == "incremental" ? " + incremental p" : " + study-form p"),
                                    .h = r.h, .dt = r.dt, .steps = r.summary.steps, .wall_seconds = r.summary.wall_seconds,
                                    .failure = r.failure};
    if (ref && r.failure.empty() && !r.centroids_end.empty())
      std::tie(row.error, row.x2_error) = case_runner::centroid_error(r.centroids_end, ref->centroids_end, ref->length);
    rows.push_back(row);
  }
  char intro[600];
  std::snprintf(intro, sizeof intro,
                "Error against run time (the study's 50 cells from rest to t = %g ms; error against the explicit run, study's form of the "
                "pressure, at h = %g um and Δt = %g s): RMS over the 50 cells of the centroid distance and of its x2 part; wall time of each "
                "run (one thread, cases run side by side). \"extrapolated\": the extrapolated Lie scheme (each step 2 L_{Δt/2}² − L_Δt).",
                kConvTime * 1e3, ref->h * 1e6, ref->dt);
  return case_runner::convergence_table(rows, (fs::path(p.out_dir) / "convergence.csv").string(), intro);
}

}  // namespace

namespace {

// The column "converged in h": what h -> 0 does to seed 1 at 3 us, from its 2h run (second order).
std::string converged_in_h(const Results& res, const std::string& base, const std::function<double(const CaseResult&)>& value) {
  auto ok = [&](const std::string& n) { return res.cases.count(n) && res.cases.at(n).failure.empty(); };
  if (!ok(base) || !ok(base + "_h0.625um")) return "";
  const auto h = grid_convergence_index({value(res.cases.at(base)), value(res.cases.at(base + "_h0.625um"))}, 2.0, 2.0);
  char b[160];
  std::snprintf(b, sizeof b, "h -> 0 moves seed 1 by %+.2g (the 2h run, second order)", h.extrapolated - value(res.cases.at(base)));
  return b;
}

// How a row's run was made (the report's column), from the run.
std::string how_run(const CaseResult& r) {
  char how[300];
  std::snprintf(how, sizeof how,
                "semi-implicit coupling (not the study's explicit one), dt = %g us, h = %g um; incremental pressure form (not the study's); %s; "
                "area term (7) during the flow",
                r.dt * 1e6, r.h * 1e6, r.spec.repulsion > 0 ? "membrane repulsion on (not in the study's model)" : "no repulsion");
  return how;
}

// A member's Re under each reading of U (reference-data/readings.csv), over its last ms.
std::vector<std::pair<std::string, double>> re_readings(const Params& p, const CaseResult& c) {
  return case_runner::u_readings((fs::path(p.out_dir) / c.spec.name / "series.csv").string(), c.t.back() - kWindow,
                                 c.summary.reynolds / c.summary.mean_velocity);
}

// The names of the arrangements at the rows' Δt that finished: seed 1 (the reported run) first.
std::vector<std::string> reported_members(const Params& p, const Results& res, const std::string& base) {
  auto ok = [&](const std::string& n) { return res.cases.count(n) && res.cases.at(n).failure.empty(); };
  std::vector<std::string> v;
  if (ok(base + "_dt1.5us")) v.push_back(base + "_dt1.5us");
  for (unsigned s : p.seeds)
    if (ok(base + "_dt1.5us_seed" + std::to_string(s))) v.push_back(base + "_dt1.5us_seed" + std::to_string(s));
  return v;
}

// A chaotic row judged as a distribution (reference/reference_table.hpp): the layer (um) or Re of
// every arrangement at the rows' Δt, their mean's u_num from their spread (s/√n) and the Δt part
// from the arrangements that finished at both 1.5 and 3 us (the same starts: the means' step, its
// noise the spread over √pairs); the h column from the 2h run.
Measured ensemble_row(const Params& p, const Results& res, const std::string& base, bool re, const std::string& note) {
  auto ok = [&](const std::string& n) { return res.cases.count(n) && res.cases.at(n).failure.empty(); };
  // Every value of the row under the reading the study is read with (Re: reference-data/readings.csv).
  // Each case's readings are read from its series once.
  const std::string chosen = re ? chosen_reading(load_readings(readings_path())) : "";
  std::map<std::string, std::vector<std::pair<std::string, double>>> readings;
  auto readings_of = [&](const CaseResult& c) -> const std::vector<std::pair<std::string, double>>& {
    auto it = readings.find(c.spec.name);
    if (it == readings.end()) it = readings.emplace(c.spec.name, re ? re_readings(p, c) : std::vector<std::pair<std::string, double>>{}).first;
    return it->second;
  };
  auto value = [&](const CaseResult& c) {
    if (!re) return c.layer * 1e6;
    for (const auto& [id, v] : readings_of(c))
      if (id == chosen) return v;
    return c.re;
  };
  Measured m{{}, {}, note};
  std::vector<double> values;
  for (const std::string& name : reported_members(p, res, base)) {
    const CaseResult& c = res.cases.at(name);
    m.ensemble.push_back({name, re ? c.re : c.layer * 1e6, readings_of(c), c.code});
    values.push_back(value(c));
  }
  // The value (the members' mean; the u_num record needs one): compare_with_reference judges the members.
  m.value = std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
  if (values.size() >= 2) {
    m.u.ensemble = sample_std(values);
    m.u.members = int(values.size());
    m.u.of_mean = true;
  }
  double fine = 0, coarse = 0;
  int pairs = 0;
  for (unsigned s = 1; s <= p.seeds.back(); ++s) {
    const std::string tail = s == 1 ? "" : "_seed" + std::to_string(s);
    const std::string a = base + "_dt1.5us" + tail, b = base + tail;
    if (ok(a) && ok(b)) {
      fine += value(res.cases.at(a));
      coarse += value(res.cases.at(b));
      ++pairs;
    }
  }
  if (pairs > 0) {
    m.u.dt = grid_convergence_index({fine / pairs, coarse / pairs}, 2.0, 1.0, 0, m.u.ensemble.value_or(NAN) / std::sqrt(double(pairs)));
    m.u.dt->label = "dt 1.5/3 us, means of " + std::to_string(pairs) + " paired arrangements";
  } else {
    m.u.missing = "the arrangements at 3 us";
  }
  m.converged_in_h = converged_in_h(res, base, value);
  m.how = "the mean of " + std::to_string(values.size()) + " arrangements; " + how_run(res.cases.at(base + "_dt1.5us"));
  return m;
}

// The rows' arrangements at their Δt as a table: each member's layer and Re (its own reading; the
// rows read every member under the chosen one), the code that made it, mean and s.
std::string rows_ensemble_table(const Params& p, const Results& res) {
  std::ostringstream md;
  for (int n : {50, 100}) {
    const std::vector<std::string> names = reported_members(p, res, base_name(n));
    if (names.empty()) continue;
    if (md.tellp() == 0)
      md << "\nThe rows' arrangements at Δt = 1.5 us (the distributions the rows are judged by: cell_free_layer_ensemble.png; seed 1 is the "
            "study's case), each with the code that made it (\"this\": the report's; else kept in paper/evidence/data/):\n\n"
            "| cells | case | seed | layer (um) | Re | code |\n|---|---|---|---|---|---|\n";
    std::vector<double> layers, re;
    for (const std::string& name : names) {
      const CaseResult& c = res.cases.at(name);
      layers.push_back(c.layer * 1e6);
      re.push_back(c.re);
      char row[300];
      std::snprintf(row, sizeof row, "| %d | %s | %u | %.3f | %.4f | %s |\n", n, name.c_str(), c.spec.seed, c.layer * 1e6, c.re,
                    c.code.empty() ? "this" : c.code.substr(0, c.code.find('\n')).c_str());
      md << row;
    }
    char row[200];
    std::snprintf(row, sizeof row, "| %d | mean of %zu (s) | | %.3f (%s) | %.4f (%s) | |\n", n, names.size(),
                  std::accumulate(layers.begin(), layers.end(), 0.0) / layers.size(), shown(sample_std(layers), "%.3f").c_str(),
                  std::accumulate(re.begin(), re.end(), 0.0) / re.size(), shown(sample_std(re), "%.4f").c_str());
    md << row;
  }
  return md.str();
}

// The rows' arrangements for the figure: each member's row values and code, and the spread of
// the layer over them against time (is it at its plateau: have the starts decorrelated?), on the
// 1 ms grid every kept run has (paper/keep_evidence.sh).
void write_ensemble_files(const Params& p, const Results& res, const std::string& base) {
  const std::vector<std::string> names = reported_members(p, res, base);
  if (names.empty()) return;
  std::ofstream f(fs::path(p.out_dir) / ("ensemble_" + base + ".dat"));
  const std::string id = "cfl_" + base.substr(1);  // the row (reference-data/cell_free_layer.csv)
  for (const ReferenceRow& row : load_reference_table(reference_table_path("cell_free_layer")))
    if (row.id == id && row.value) f << "# study " << *row.value << " um (" << id << ")\n";
  f << "# the arrangements at the rows' Δt: index, seed, layer (um, mean of the walls, last ms), Re (its own reading), code (- : this build)\n";
  for (std::size_t k = 0; k < names.size(); ++k) {
    const CaseResult& c = res.cases.at(names[k]);
    f << k + 1 << " " << c.spec.seed << " " << c.layer * 1e6 << " " << c.re << " " << (c.code.empty() ? "-" : c.code) << "\n";
  }
  std::ofstream g(fs::path(p.out_dir) / ("spread_" + base + ".dat"));
  g << "# the layer (mean of the walls) over the " << names.size() << " arrangements at each ms: t (ms), mean (um), s (um), members\n";
  std::vector<std::vector<double>> layers;  // each member's layer against its samples, um
  for (const std::string& name : names) layers.push_back(layer_series_um(res.cases.at(name)));
  const CaseResult& first = res.cases.at(names.front());
  for (double ms = 0; ms <= first.t.back() * 1e3 + 1e-9; ms += 1) {
    std::vector<double> at;
    for (std::size_t m = 0; m < names.size(); ++m) {
      const double v = case_runner::value_at(res.cases.at(names[m]).t, layers[m], ms * 1e-3);
      if (std::isfinite(v)) at.push_back(v);
    }
    if (at.size() < 2) continue;
    double mean = 0;
    for (double v : at) mean += v / at.size();
    g << ms << " " << mean << " " << sample_std(at) << " " << at.size() << "\n";
  }
}

// A layer (um) or Re row with its u_num: the Δt part from the scene's 3 us and the
// halved run (two levels, first order, Fs 3), the arrangements' spread (the study's case and the
// other seeds, at 3 us), the window noise of the reported run (the last 5 windows of 1 ms); the
// h column from the 2h run.
Measured with_uncertainty(const Params& p, const Results& res, const std::string& base, const std::string& reported, bool re,
                          const std::string& note) {
  auto ok = [&](const std::string& n) { return res.cases.count(n) && res.cases.at(n).failure.empty(); };
  auto value = [&](const CaseResult& c) { return re ? c.re : c.layer * 1e6; };
  const CaseResult& r = res.cases.at(reported);
  Measured m{value(r), {}, note};
  if (reported == base + "_dt1.5us") return ensemble_row(p, res, base, re, note);
  std::vector<double> members;
  if (ok(base)) members.push_back(value(res.cases.at(base)));
  for (unsigned s : p.seeds)
    if (ok(base + "_seed" + std::to_string(s))) members.push_back(value(res.cases.at(base + "_seed" + std::to_string(s))));
  if (members.size() >= 2) {
    m.u.ensemble = sample_std(members);
    m.u.members = members.size();
  }
  if (members.size() < p.seeds.size() + 1)
    m.u.missing += std::string(m.u.missing.empty() ? "" : ", ") + "the arrangements (" + std::to_string(members.size()) + " of " +
                   std::to_string(p.seeds.size() + 1) + ")";
  if (ok(base) && ok(base + "_dt1.5us")) {
    // The arrangements' spread tells the Δt pair whether its difference is noise.
    m.u.dt = grid_convergence_index({value(res.cases.at(base + "_dt1.5us")), value(res.cases.at(base))}, 2.0, 1.0, 0,
                                    m.u.ensemble.value_or(NAN));
    m.u.dt->label = "dt 1.5/3 us";
  } else {
    m.u.missing = "the Δt-halved run";
  }
  m.u.window = window_noise(r.t, re ? r.reynolds : layer_series_um(r), kWindow, 5);
  m.converged_in_h = converged_in_h(res, base, value);
  m.how = how_run(r);
  return m;
}

}  // namespace

Results run(const Params& p) {
  Results res;
  res.cases = case_runner::run_selected(cases(p), p.only, "cell_free_layer", p.out_dir, [&](const Case& c) { return run_case(p, c); });
  std::erase_if(res.cases, [](const auto& kv) { return kv.second.failure == case_runner::kNotRun; });  // --collect
  if (!p.only.empty()) return res;

  auto ok = [&](const std::string& n) { return res.cases.count(n) && res.cases.at(n).failure.empty(); };
  // A row (and its figures) reports the finest Δt that finished: the halved run or the scene's 3 us.
  auto reported_run = [&](const std::string& base) { return ok(base + "_dt1.5us") ? base + "_dt1.5us" : base; };
  for (int n : {50, 100}) {
    const std::string name = base_name(n), tag = std::to_string(n);
    const std::string reported = reported_run(name);
    if (!ok(reported)) {
      const std::string why = res.cases.count(reported) ? "run stopped: " + res.cases.at(reported).failure : "not run";
      for (const char* id : {"hct_", "cfl_", "re_"}) res.measured[id + tag] = {{}, {}, why};
      continue;
    }
    if (p.quick) continue;  // the quick case has its own record (below)
    const CaseResult& r = res.cases.at(reported);
    char note[300];
    std::snprintf(note, sizeof note, "%s, over %.4g-%.4g s", reported.c_str(), r.t.back() - kWindow, r.t.back());
    res.measured["hct_" + tag] = {r.hct, {}, note};
    res.measured["hct_" + tag].u.other = "geometry of the prepared cells (round-off)";
    res.measured["hct_" + tag].u.other_value = 0.0;
    res.measured["hct_" + tag].how = "the prepared cells' areas over L H (geometry)";
    std::snprintf(note, sizeof note, "%s: lower wall %.3f um, upper wall %.3f um, over %.4g-%.4g s; over the run's second half %.3f um; 100/Hct = %.2f um (ours)",
                  reported.c_str(), r.layer_lower * 1e6, r.layer_upper * 1e6, r.t.back() - kWindow, r.t.back(), r.layer_late * 1e6, 100 / r.hct);
    res.measured["cfl_" + tag] = with_uncertainty(p, res, name, reported, false, note);
    res.measured["re_" + tag] = with_uncertainty(p, res, name, reported, true, reported + ", mean over the last ms");
    // The row under each reading of U (reference-data/readings.csv), over the same last ms.
    Measured& re_row = res.measured["re_" + tag];
    re_row.readings = re_readings(p, r);
    if (!re_row.ensemble.empty())  // an ensemble row: each reading's mean over the members
      for (auto& [id, v] : re_row.readings)
        v = ensemble_statistics(re_row.ensemble, 0, id).mean;
  }
  if (!p.quick)
    for (int n : {50, 100}) write_ensemble_files(p, res, base_name(n));
  {  // The runs the figures draw: each row's reported run (plot.gp).
    std::ofstream f(fs::path(p.out_dir) / "figure_runs.txt");
    for (int n : {50, 100}) f << base_name(n) << " " << reported_run(base_name(n)) << "\n";
  }
  if (!p.quick && !p.study_only) {  // the quick run has one arrangement and no evidence runs
    res.ensemble_md = ensemble_table(p, res) + rows_ensemble_table(p, res) + early_layer_table(res) + form_table(res);
    std::ofstream(fs::path(p.out_dir) / "ensemble.md") << res.ensemble_md;
  }
  if (p.convergence && !p.quick) {
    res.convergence_md = convergence_table(p, res);
    std::ofstream(fs::path(p.out_dir) / "convergence.md") << res.convergence_md;
  }
  {
    std::ofstream f(fs::path(p.out_dir) / "cases.csv");
    f << "case,role,cells,seed,h_um,dt_s,steps,wall_seconds,layer_um,layer_lower_um,layer_upper_um,layer_second_half_um,hct_percent,reynolds,repulsion_N_per_m,repulsion_steps,failure\n";
    for (const auto& [name, r] : res.cases)
      f << name << "," << r.spec.role << "," << r.spec.cells << "," << r.spec.seed << "," << r.h * 1e6 << "," << r.dt << "," << r.summary.steps << ","
        << r.summary.wall_seconds << "," << r.layer * 1e6 << "," << r.layer_lower * 1e6 << "," << r.layer_upper * 1e6 << "," << r.layer_late * 1e6 << "," << r.hct << "," << r.re
        << "," << r.spec.repulsion << "," << r.repulsion_steps << "," << (r.failure.empty() ? "" : "stopped") << "\n";
  }
  if (p.quick)
    for (const auto& [name, r] : res.cases) {
      if (!r.failure.empty()) continue;
      const std::string what = " (" + std::to_string(r.spec.cells) + " cells, seed " + std::to_string(r.spec.seed) + "), last ms of 3 ms";
      res.quick_record["cfl_" + name] = {"cell-free layer, mean of the walls" + what, "um", r.layer * 1e6};
      res.quick_record["re_" + name] = {"Reynolds number" + what, "", r.re};
      res.quick_record["hct_" + name] = {"hematocrit" + what, "%", r.hct};
    }
  return res;
}

}  // namespace rbc::cell_free_layer
