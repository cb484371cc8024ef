#include "single_cell_migration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "diagnostics/flow_diagnostics.hpp"
#include "common/case_runner.hpp"
#include "io/csv.hpp"
#include "reference/uncertainty.hpp"
#include "mesh/channel_mesh.hpp"

namespace rbc::single_cell_migration {

namespace fs = std::filesystem;

namespace {

const std::vector<double> kFigure3Times = {0.0, 0.05e-3, 0.10e-3, 0.20e-3, 0.30e-3, 0.50e-3, 0.80e-3,
                                           0.90e-3, 1.00e-3, 1.25e-3, 1.50e-3, 2.00e-3, 3.00e-3, 7.50e-3};
// The narrow channel's movie (frames.dat over the run; experiments/common/movie.gp).
constexpr int kMovieFrames = 100;

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
    if (line.rfind("# t", 0) == 0) { flush(); header = line.substr(0, line.find(';')) + "; x1 from the centroid (um), x2 (um)"; }
    else if (!line.empty() && line[0] != '#') {
      std::stringstream ss(line);
      double x, y;
      ss >> x >> y;
      pts.push_back({x, y});
    }
  }
  flush();
}

// A case's run time, in explicit node-steps: steps × mesh nodes, a semi-implicit step counted as
// kSemiImplicitStepCost explicit ones on the same mesh (three of them in the extrapolated scheme). Measured in `make reproduce`: the wide channel's semi-implicit step (320 × 160, Q = 4)
// 12.3 ms, the narrow channel's explicit step (160 × 80) 0.97 ms: 3.2 times per node. Ordering by
// steps alone started the three wide runs (the longest, 28 min each) last: 76 min in all against
// 68 min for this order (both schedules worked out from the run times measured in that run).
constexpr double kSemiImplicitStepCost = 3.2;
double estimated_work(const Scene& s) {
  const double nodes = double(ChannelMesh::make(s.length, s.height, s.mesh_size).velocity_nodes());
  return std::round(s.end / s.dt) * nodes * (s.coupling == "semi-implicit" ? kSemiImplicitStepCost : 1.0) * (s.scheme == "lie" ? 1.0 : 3.0);
}

// The suffix of each swelling ratio's rows in reference-data/single_cell_migration.csv.
const std::map<double, std::string> kRowIds = {{0.55, "s055"}, {0.7, "s07"}, {1.0, "s10"}};

// The narrow runs without the area term during the flow (one reading of the study for its Re).
constexpr const char* kNoAreaTermPrefix = "re_flow_without_area_term_";

std::string re_case_name(double h, double dt, double s) {
  char b[64];
  std::snprintf(b, sizeof b, "re_h%g_dt%g_%s", h * 1e6, dt, tag(s).c_str());
  return b;
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

// The work-precision table: error of the centroid height at conv_time against the finest run,
// wall time, and the observed orders in Δt (successive differences at fixed h) and in h (the
// smallest Δt of each h, explicit coupling).
template <class ConvJobs>
void convergence_table(const Params& p, const ConvJobs& conv, Results& res) {
  const ConvergenceRun* ref = nullptr;
  for (const auto& j : conv) {
    if (!res.cases.count(j.name) || !res.cases.at(j.name).failure.empty()) continue;
    const Case& c = res.cases.at(j.name);
    ConvergenceRun r{j.coupling, j.h, j.dt, c.summary.steps, c.summary.wall_seconds, c.summary.cells.at(0).centroid.y(), 0};
    res.convergence.push_back(r);
  }
  for (const auto& r : res.convergence)
    if (r.coupling == "explicit" && (!ref || r.h < ref->h || (r.h == ref->h && r.dt < ref->dt))) ref = &r;
  if (!ref) return;
  const double y_ref = ref->y, h_ref = ref->h, dt_ref = ref->dt;
  // Richardson extrapolation in Δt (first order) of each pair Δt, 2Δt of a coupling and h:
  // y_R = 2 y(Δt) − y(2Δt), at the cost of both runs (its kind "<coupling> Richardson"); not from
  // the reference itself (its error would be the 2Δt run's).
  std::vector<ConvergenceRun> extrapolated;
  for (const auto& fine : res.convergence)
    for (const auto& coarse : res.convergence)
      if (&fine != ref && fine.coupling != case_runner::kExtrapolatedKind && coarse.coupling == fine.coupling &&
          case_runner::halving_pair(fine.h, fine.dt, coarse.h, coarse.dt))
        extrapolated.push_back({fine.coupling + " Richardson", fine.h, fine.dt, fine.steps + coarse.steps,
                                fine.wall_seconds + coarse.wall_seconds, richardson_extrapolate(fine.y, coarse.y, 2, 1), 0});
  ref = nullptr;  // (the insertion below may move the runs: y_ref, h_ref, dt_ref hold its values)
  res.convergence.insert(res.convergence.end(), extrapolated.begin(), extrapolated.end());
  for (auto& r : res.convergence) r.error = std::abs(r.y - y_ref);
  std::ofstream csv(fs::path(p.out_dir) / "convergence.csv");
  csv << "coupling,h_um,dt_s,steps,wall_seconds,y_um,error_um\n";
  for (const auto& r : res.convergence)
    csv << r.coupling << "," << r.h * 1e6 << "," << r.dt << "," << r.steps << "," << r.wall_seconds << "," << r.y * 1e6 << ","
        << r.error * 1e6 << "\n";
  std::ostringstream md;
  md << "Error against run time (narrow channel, s* = 0.55 from (5, 3) um, SI constants): the error of the centroid "
        "height at t = " << p.conv_time * 1e3 << " ms against the finest run (explicit, h = " << h_ref * 1e6 << " um, Δt = " << dt_ref
     << " s: y = " << y_ref * 1e6 << " um), wall time of each run on one thread. Errors below that run's own error are not resolved. "
        "Rows \"Richardson\": 2 y(Δt) − y(2Δt) from the runs at Δt and 2Δt of the same coupling and h, at the wall time of both "
        "(none from the reference itself). Rows \"" << case_runner::kExtrapolatedKind << "\": the semi-implicit coupling in the extrapolated Lie scheme "
        "(each step 2 L_{Δt/2}² − L_Δt) with the incremental form of the pressure.\n\n";
  md << "| coupling | h (um) | Δt (s) | steps | wall (s) | y (um) | error (um) | observed order in Δt |\n|---|---|---|---|---|---|---|---|\n";
  // Observed Δt order at fixed h: log2 of the ratio of successive differences (Δt halving).
  for (const std::string& coupling : {std::string("explicit"), std::string("explicit Richardson"), std::string("semi-implicit"),
                                      std::string("semi-implicit Richardson"), case_runner::kExtrapolatedKind})
    for (double h : {0.5e-6, 0.25e-6, 0.125e-6}) {
      std::vector<const ConvergenceRun*> runs;
      for (const auto& r : res.convergence)
        if (r.coupling == coupling && r.h == h) runs.push_back(&r);
      std::sort(runs.begin(), runs.end(), [](auto* a, auto* b) { return a->dt > b->dt; });
      for (std::size_t k = 0; k < runs.size(); ++k) {
        std::string order;
        if (k >= 2) {
          const double d1 = runs[k - 2]->y - runs[k - 1]->y, d2 = runs[k - 1]->y - runs[k]->y;
          if (d2 != 0) order = std::to_string(std::log2(std::abs(d1 / d2))).substr(0, 4);
        }
        char row[200];
        std::snprintf(row, sizeof row, "| %s | %g | %.3g | %ld | %.1f | %.5f | %.2e | %s |\n", coupling.c_str(), h * 1e6, runs[k]->dt,
                      runs[k]->steps, runs[k]->wall_seconds, runs[k]->y * 1e6, runs[k]->error * 1e6, order.c_str());
        md << row;
      }
    }
  // Observed h order: the smallest Δt of each h, explicit.
  std::vector<double> yh;
  for (double h : {0.5e-6, 0.25e-6, 0.125e-6}) {
    const ConvergenceRun* best = nullptr;
    for (const auto& r : res.convergence)
      if (r.coupling == "explicit" && r.h == h && (!best || r.dt < best->dt)) best = &r;
    if (best) yh.push_back(best->y);
  }
  if (yh.size() == 3 && yh[1] != yh[2])
    md << "\nObserved order in h (explicit, smallest Δt of each h = 0.5, 0.25, 0.125 um): "
       << std::log2(std::abs((yh[0] - yh[1]) / (yh[1] - yh[2]))) << ".\n";
  res.convergence_summary = md.str();
  std::ofstream(fs::path(p.out_dir) / "convergence.md") << res.convergence_summary;
}

// u_num of a Re row: the Δt part from the two Δt of the finest h of the Re evidence
// runs (a proxy: the row's own h has one Δt; two levels, so Fs = 3), and the window's part (the
// row averages the last sample interval: the spread of the last 5 such means).
NumericalUncertainty re_uncertainty(const Params& p, const Results& res, double s) {
  NumericalUncertainty u;
  auto re_of = [&](const std::string& name) -> double {
    const auto it = res.cases.find(name);
    return it == res.cases.end() || !it->second.failure.empty() ? NAN : it->second.summary.reynolds;
  };
  std::map<double, std::vector<double>> dts;  // h -> Δt, smallest first
  for (const auto& [h, dt] : p.re_runs) dts[h].push_back(dt);
  if (!dts.empty()) {
    auto& [h, v] = *dts.begin();
    std::sort(v.begin(), v.end());
    if (v.size() >= 2) {
      const double fine = re_of(re_case_name(h, v[0], s)), coarse = re_of(re_case_name(h, v[1], s));
      if (std::isfinite(fine) && std::isfinite(coarse)) {
        u.dt = grid_convergence_index({fine, coarse}, v[1] / v[0], 1.0);
        char label[96];
        std::snprintf(label, sizeof label, "dt %g/%g s at h = %g um", v[0], v[1], h * 1e6);
        u.dt->label = label;
      }
    }
  }
  if (!u.dt) u.missing = "the Δt pair at h = 0.25 um";
  const std::string series = (fs::path(p.out_dir) / ("narrow_" + p.membrane.units + "_" + tag(s)) / "series.csv").string();
  if (fs::exists(series)) u.window = window_noise(csv_column(series, "t"), csv_column(series, "reynolds"), p.sample_every, 5);
  return u;
}

// The "converged in h" column of a Re row: the h sequence 0.5/0.25/0.125 um (largest Δt of each
// coarser h), its observed order and the extrapolation h -> 0.
std::string re_converged_in_h(const Params& p, const Results& res, double s) {
  std::map<double, double> largest;  // h -> largest Δt
  for (const auto& [h, dt] : p.re_runs) largest[h] = std::max(largest[h], dt);
  std::vector<double> seq = {res.cases.count("narrow_" + p.membrane.units + "_" + tag(s)) ? res.cases.at("narrow_" + p.membrane.units + "_" + tag(s)).summary.reynolds : NAN};
  for (const auto& [h, dt] : largest) {
    const auto it = res.cases.find(re_case_name(h, dt, s));
    seq.push_back(it == res.cases.end() || !it->second.failure.empty() ? NAN : it->second.summary.reynolds);
  }
  std::vector<double> ok;
  for (double v : seq)
    if (std::isfinite(v)) ok.push_back(v); else break;
  if (ok.size() < 2) return "";
  const RefinementUncertainty r = grid_convergence_index(ok, 2.0, 2.0);
  char b[160];
  std::snprintf(b, sizeof b, "%.4f (h -> 0 from %zu meshes; %s)", r.extrapolated, ok.size(), r.describe(2).c_str());
  return b;
}

// What could explain the Reynolds numbers with the cell: their h- and Δt-convergence,
// the averaging window and the definition of U. Markdown for the report, from the narrow runs.
void re_evidence_table(const Params& p, Results& res) {
  const FluidProperties fluid = Scene{}.fluid;
  const double H = 10e-6;
  std::map<double, std::string> study;  // the study's Re, with its own digits
  for (const ReferenceRow& r : load_reference_table(reference_table_path("single_cell_migration")))
    for (const auto& [s, id] : kRowIds)
      if (r.id == "re_" + id) study[s] = r.value_text;
  auto re_of = [&](const std::string& name) -> double {
    const auto it = res.cases.find(name);
    return it == res.cases.end() || !it->second.failure.empty() ? NAN : it->second.summary.reynolds;
  };
  // h-sequence: the largest Δt of each h in re_runs, then the row's own run; Δt: two steps at one h.
  std::map<double, std::vector<double>> dts;  // h -> Δt, largest first
  for (const auto& [h, dt] : p.re_runs) dts[h].push_back(dt);
  for (auto& [h, v] : dts) std::sort(v.rbegin(), v.rend());
  std::ostringstream md;
  md << "Re with the cell against the mesh size (explicit coupling, to " << p.narrow_end * 1e3
     << " ms; Δt of each h in brackets), the observed order, the Richardson extrapolation h → 0 and the change when Δt is "
        "halved:\n\n| s* | ";
  for (auto it = dts.rbegin(); it != dts.rend(); ++it) md << "h = " << it->first * 1e6 << " um (" << it->second.front() << " s) | ";
  md << "h = " << p.narrow_mesh * 1e6 << " um (" << p.narrow_dt << " s): the row | observed order | extrapolated | Δt halved at h = "
     << dts.begin()->first * 1e6 << " um | study |\n|---|";
  for (std::size_t k = 0; k < dts.size() + 5; ++k) md << "---|";
  md << "\n";
  for (double s : p.swelling_ratios) {
    std::vector<double> seq;
    for (auto it = dts.rbegin(); it != dts.rend(); ++it) seq.push_back(re_of(re_case_name(it->first, it->second.front(), s)));
    seq.push_back(re_of("narrow_" + p.membrane.units + "_" + tag(s)));
    const std::size_t n = seq.size();
    const double order = n >= 3 ? std::log2(std::abs((seq[n - 3] - seq[n - 2]) / (seq[n - 2] - seq[n - 1]))) : NAN;
    const double extrap = order > 0.3 ? seq[n - 1] + (seq[n - 1] - seq[n - 2]) / (std::pow(2.0, order) - 1) : NAN;
    const auto& fine = *dts.begin();
    const double dt_change = fine.second.size() >= 2 ? re_of(re_case_name(fine.first, fine.second[1], s)) -
                                                           re_of(re_case_name(fine.first, fine.second[0], s))
                                                     : NAN;
    char row[320];
    md << "| " << s << " | ";
    for (double v : seq) { std::snprintf(row, sizeof row, "%.4f | ", v); md << row; }
    std::snprintf(row, sizeof row, "%.2f | %.4f | %+.1e | %s |\n", order, extrap, dt_change, study[s].c_str());
    md << row;
  }
  md << "\nThe averaging window and the definition of U, at h = " << p.narrow_mesh * 1e6
     << " um: U over the whole cross-section (ours, reading the study's Section 2) averaged over the last sample interval "
        "(the row), over the last " << p.re_window * 1e3 << " ms and over the whole run from rest; and the plasma alone "
        "(lib/diagnostics/flow_diagnostics.hpp), its flux per unit channel height and its mean velocity over the open height "
        "of each section, averaged over the samples of the last " << p.re_window * 1e3 << " ms:\n\n"
        "| s* | U over the section, last sample interval (the row) | last " << p.re_window * 1e3 << " ms | whole run | plasma flux / H | "
        "plasma over its open height | study |\n|---|---|---|---|---|---|---|\n";
  for (double s : p.swelling_ratios) {
    const std::string name = "narrow_" + p.membrane.units + "_" + tag(s);
    if (!res.cases.count(name) || !res.cases.at(name).failure.empty()) continue;
    const std::string series = (fs::path(p.out_dir) / name / "series.csv").string();
    const auto t = csv_column(series, "t"), U = csv_column(series, "mean_velocity"), Qp = csv_column(series, "plasma_flux_velocity"),
               Up = csv_column(series, "plasma_open_velocity");
    auto mean = [&](const std::vector<double>& v, double from) {
      double sum = 0;
      int k = 0;
      for (std::size_t i = 1; i < t.size(); ++i)
        if (t[i] > from + 1e-12) { sum += v[i]; ++k; }
      return k ? reynolds_number(sum / k, fluid, H) : NAN;
    };
    const double from = t.back() - p.re_window;
    char row[256];
    std::snprintf(row, sizeof row, "| %g | %.4f | %.4f | %.4f | %.4f | %.4f | %s |\n", s, res.cases.at(name).summary.reynolds,
                  mean(U, from), mean(U, 0.0), mean(Qp, from), mean(Up, from), study[s].c_str());
    md << row;
  }
  md << "\nThe area term (7) only while the shapes are prepared, not during the flow (the study's text can be read either way; "
        "the rows keep it during the flow), at h = " << p.narrow_mesh * 1e6 << " um and the rows' Δt:\n\n"
        "| s* | Re, area term during the flow (the row) | Re, area term off during the flow | its area drift at the end | study |\n|---|---|---|---|---|\n";
  for (double s : p.swelling_ratios) {
    const std::string with = "narrow_" + p.membrane.units + "_" + tag(s), without = kNoAreaTermPrefix + tag(s);
    const auto a = res.cases.find(with), b = res.cases.find(without);
    if (a == res.cases.end() || b == res.cases.end() || !a->second.failure.empty() || !b->second.failure.empty()) continue;
    char row[256];
    std::snprintf(row, sizeof row, "| %g | %.4f | %.4f | %+.2e | %s |\n", s, a->second.summary.reynolds, b->second.summary.reynolds,
                  b->second.summary.cells.empty() ? NAN : b->second.summary.cells[0].area_drift, study[s].c_str());
    md << row;
  }
  res.re_evidence = md.str();
  std::ofstream(fs::path(p.out_dir) / "re_evidence.md") << res.re_evidence;
}

namespace {

struct ConvJob { std::string name, coupling; double h, dt; };

// The cases of a run with these parameters, the longest first (estimated work), and the
// convergence runs among them.
std::vector<Job> build_jobs(const Params& p, std::vector<ConvJob>& conv) {
  // The cases: the narrow channel under the chosen reading (Figures 3, 4), the other reading over
  // the first millisecond (the units evidence), the wide channel (Figure 5).
  std::vector<Job> jobs;
  for (double s : p.swelling_ratios) {
    Scene sc = channel_scene(20e-6, 10e-6, p.narrow_mesh, 0.5556, p.narrow_dt, p.narrow_end, p.sample_every);
    sc.cells.push_back({{5e-6, 3e-6}, s, 0.0});
    sc.membrane_constants = p.membrane;
    sc.snapshots = kFigure3Times;
    sc.frames = kMovieFrames;
    sc.source = "single_cell_migration narrow " + p.membrane.units + " s*=" + std::to_string(s);
    jobs.push_back({"narrow_" + p.membrane.units + "_" + tag(s), sc});
    if (p.quick) continue;
    // Re with the cell against h and Δt: the same run on coarser meshes and a smaller step.
    if (p.re_convergence)
      for (const auto& [h, dt] : p.re_runs) {
        Scene r = channel_scene(20e-6, 10e-6, h, 0.5556, dt, p.narrow_end, p.sample_every);
        r.cells = sc.cells;
        r.membrane_constants = p.membrane;
        r.source = "single_cell_migration " + re_case_name(h, dt, s);
        jobs.push_back({re_case_name(h, dt, s), r});
      }
    // The area term (7) only while preparing the shape, not during the flow:
    // one reading of the study we had not tried for its Re offsets.
    if (p.re_convergence) {
      Scene r = sc;
      r.area_penalty = false;
      r.snapshots = {0.0};
      r.source = "single_cell_migration " + std::string(kNoAreaTermPrefix) + tag(s);
      jobs.push_back({kNoAreaTermPrefix + tag(s), r});
    }
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
    wide.membrane_constants = p.membrane;
    wide.coupling = p.wide_coupling;
    wide.advection_substeps = p.wide_substeps;
    wide.snapshots = {0.0, 0.1, 0.2, 0.4, 0.8};
    char src[160];
    std::snprintf(src, sizeof src, "single_cell_migration wide %s s*=%g %s dt=%g s end=%g s", p.membrane.units.c_str(), s,
                  p.wide_coupling.c_str(), p.wide_dt, p.wide_end);
    wide.source = src;
    jobs.push_back({"wide_" + p.membrane.units + "_" + tag(s), wide});
  }
  // Error against run time: short narrow-channel runs over h and Δt, both couplings, and the
  // semi-implicit one in the extrapolated Lie scheme (incremental form).
  if (!p.quick && p.convergence)
    for (const auto& [coupling, table] : {std::pair{std::string("explicit"), p.conv_explicit},
                                          std::pair{std::string("semi-implicit"), p.conv_semi_implicit},
                                          std::pair{case_runner::kExtrapolatedKind, p.conv_extrapolated}})
      for (const auto& [h, dts] : table)
        for (double dt : dts) {
          char name[96];
          std::snprintf(name, sizeof name, "conv_%s_h%g_dt%g", coupling.c_str(), h * 1e6, dt);
          Scene sc = channel_scene(20e-6, 10e-6, h, 0.5556, dt, std::round(p.conv_time / dt) * dt, p.conv_time / 25);
          sc.cells.push_back({{5e-6, 3e-6}, 0.55, 0.0});
          sc.membrane_constants = p.membrane;
          sc.coupling = case_runner::coupling_of(coupling);
          sc.scheme = case_runner::scheme_of(coupling);
          if (coupling == case_runner::kExtrapolatedKind) sc.projection = "incremental";
          sc.advection_substeps = sc.advection_substeps_for(dt);
          char src[160];
          std::snprintf(src, sizeof src, "single_cell_migration convergence %s h=%g um dt=%g s", coupling.c_str(), h * 1e6, dt);
          sc.source = src;
          jobs.push_back({name, sc});
          conv.push_back({name, coupling, h, dt});
        }
  // The longest first: GNU parallel (make reproduce) starts them in this order, so that the last
  // to start are short and the cores finish together.
  std::stable_sort(jobs.begin(), jobs.end(), [](const Job& a, const Job& b) { return estimated_work(a.scene) > estimated_work(b.scene); });
  if (p.study_only)  // the study's runs, and the error against run time (its whole ladder: under a minute of one core)
    std::erase_if(jobs, [&](const Job& j) {
      return j.name.rfind("narrow_" + p.membrane.units + "_", 0) != 0 && j.name.rfind("wide_", 0) != 0 && j.name.rfind("conv_", 0) != 0;
    });
  return jobs;
}

}  // namespace

std::vector<std::string> case_names(const Params& p) {
  std::vector<ConvJob> conv;
  std::vector<std::string> names;
  for (const Job& j : build_jobs(p, conv)) names.push_back(j.name);
  return names;
}

Results run(const Params& p) {
  std::vector<ConvJob> conv;
  std::vector<Job> jobs = build_jobs(p, conv);
  // --only: that case (an exact name from --list-cases), or every case whose name starts with it.
  if (!p.only.empty()) {
    const bool exact = std::any_of(jobs.begin(), jobs.end(), [&](const Job& j) { return j.name == p.only; });
    std::erase_if(jobs, [&](const Job& j) { return exact ? j.name != p.only : j.name.rfind(p.only, 0) != 0; });
    if (jobs.empty()) throw std::invalid_argument("--only " + p.only + ": no such case (build/bin/single_cell_migration --list-cases lists them)");
  }
  // One case after the other, each with p.threads (0: every core); to run cases side by side,
  // GNU parallel or a Slurm array runs them as separate processes (--list-cases, --only; the
  // README), as make reproduce does.
  Results res;
  for (const Job& job : jobs) {
    const fs::path out = fs::path(p.out_dir) / job.name;
    Case c;
    c.name = job.name;
    c.swelling_ratio = job.scene.cells[0].swelling_ratio;
    c.units = job.scene.membrane_constants.units;
    // Run, or read back a finished or failed run (an unstable case is reported, not hidden: its
    // rows fail with the cause). A signal stops the whole experiment (RunInterrupted).
    const case_runner::CaseRun run = case_runner::run_or_reuse(
        job.scene, out.string(), {.threads = p.threads, .progress = p.progress, .resume = p.resume, .reuse = p.reuse || p.collect,
                                      .collect = p.collect, .label = job.name});
    c.summary = run.summary;
    c.failure = run.failure;
    if (c.failure.empty()) {
      c.t = csv_column((out / "series.csv").string(), "t");
      c.y = csv_column((out / "series.csv").string(), "cell0_y");
      c.hematocrit0 = csv_column((out / "series.csv").string(), "hematocrit").front();
      const double mid = 0.5 * job.scene.height;
      for (std::size_t k = 0; k < c.t.size(); ++k)
        if (std::abs(c.y[k] - mid) < p.centreline_band) { c.time_to_centreline = c.t[k]; break; }
      if (fs::exists(out / "snapshots.dat")) write_centred_snapshots(out / "snapshots.dat", out / "snapshots_centred.dat");
    }
    res.cases[job.name] = c;
  }
  if (!conv.empty() && (p.only.empty() || std::string("conv").rfind(p.only, 0) == 0 || p.only.rfind("conv", 0) == 0))
    convergence_table(p, conv, res);
  if (!p.quick && p.re_convergence && p.only.empty() && !p.study_only) re_evidence_table(p, res);
  if (!p.only.empty()) return res;  // a part: no comparison with the study

  // The study's rows (reference-data/single_cell_migration.csv).
  auto narrow = [&](double s) -> const Case& { return res.cases.at("narrow_" + p.membrane.units + "_" + tag(s)); };
  const std::map<double, std::string>& ids = kRowIds;
  for (double s : p.swelling_ratios) {
    if (!ids.count(s)) continue;
    const Case& c = narrow(s);
    const std::string id = ids.at(s);
    if (c.failure == case_runner::kNotRun) continue;  // --collect, not finished: its rows say "not run"
    if (!c.failure.empty()) {
      for (const char* row : {"hct_", "re_", "centreline_"}) res.measured[std::string(row) + id] = {{}, false, "run failed: " + c.failure};
      continue;
    }
    // The hematocrit of the set-up: the prepared cell at t = 0 (its area drift during the run is
    // its own quantity, in cases.csv and the quick record).
    char hnote[96];
    std::snprintf(hnote, sizeof hnote, "prepared cell, t = 0; %.4f %% at the end", c.summary.hematocrit);
    res.measured["hct_" + id] = {c.hematocrit0, {}, hnote};
    if (p.quick) {
      const CellState& cell = c.summary.cells.at(0);
      const std::string k = "_" + tag(c.swelling_ratio), what = ", s* = " + std::to_string(c.swelling_ratio).substr(0, 4) + ", at " +
                                                               std::to_string(p.narrow_end * 1e3).substr(0, 4) + " ms";
      res.quick_record["y" + k] = {"centroid height" + what, "um", cell.centroid.y() * 1e6};
      res.quick_record["x" + k] = {"centroid x1 (unwrapped)" + what, "um", cell.centroid.x() * 1e6};
      res.quick_record["re" + k] = {"Reynolds number, last sample interval" + what, "", c.summary.reynolds};
      res.quick_record["drift" + k] = {"area drift" + what, "", cell.area_drift};
      res.quick_record["rear" + k] = {"rear concavity" + what, "", cell.shape.rear_concavity};
      res.quick_record["length" + k] = {"x1-extent" + what, "um", cell.shape.length * 1e6};
      res.quick_record["hct0" + k] = {"hematocrit of the prepared cell" + what.substr(0, what.find(", at")), "%", c.hematocrit0};
    }
    {
      // The geometry row's numerical part: none but round-off (the prepared polygon's exact area).
      auto& m = res.measured["hct_" + id];
      m.u.other = "geometry of the prepared polygon (round-off)";
      m.u.other_value = 0.0;
      m.how = "prepared shape at t = 0 (area term (7) while preparing)";
    }
    if (!p.quick) {
      res.measured["re_" + id] = {c.summary.reynolds, {}, ""};
      res.measured["re_" + id].u = re_uncertainty(p, res, s);
      res.measured["re_" + id].converged_in_h = re_converged_in_h(p, res, s);
      char how[200];
      std::snprintf(how, sizeof how, "explicit coupling (the study's), h = %g um, dt = %g s; study's pressure form; area term (7) during the flow",
                    p.narrow_mesh * 1e6, p.narrow_dt);
      res.measured["re_" + id].how = how;
      // The row under each reading of U (reference-data/readings.csv), at the row's last sample.
      const std::string series = (fs::path(p.out_dir) / ("narrow_" + p.membrane.units + "_" + tag(s)) / "series.csv").string();
      res.measured["re_" + id].readings =
          case_runner::u_readings(series, csv_column(series, "t").back(), c.summary.reynolds / c.summary.mean_velocity);
      const double y7 = value_at(c.t, c.y, p.centreline_check_time);
      char note[64];
      std::snprintf(note, sizeof note, "y(%.1f ms) = %.3f um", p.centreline_check_time * 1e3, y7 * 1e6);
      res.measured["centreline_" + id] = {{}, std::abs(y7 - 5e-6) < p.centreline_band, note};
      const std::string kind = c.summary.cells[0].shape.kind;
      if (id != "s10") res.measured["parachute_" + id] = {{}, kind == "parachute", "shape at 7.5 ms: " + kind};
      else res.measured["bullet_s10"] = {{}, kind == "bullet", "shape at 7.5 ms: " + kind};
    }
  }
  // The rows below need the narrow and wide cases of the chosen reading; a stopped case of the
  // other reading only leaves its row of the units evidence without numbers.
  bool all_ran = true;
  for (const auto& [name, c] : res.cases)
    if (name.rfind("narrow_" + p.membrane.units + "_", 0) == 0 || name.rfind("wide_", 0) == 0) all_ran = all_ran && c.failure.empty();
  if (!p.quick && ids.size() == p.swelling_ratios.size() && all_ran) {
    // s* = 1 slowest: its time to reach the centreline band is the largest.
    auto ttc = [&](double s) { const double t = narrow(s).time_to_centreline; return t < 0 ? INFINITY : t; };
    char note[96];
    std::snprintf(note, sizeof note, "times to centreline %.2f, %.2f, %.2f ms", ttc(0.55) * 1e3, ttc(0.7) * 1e3, ttc(1.0) * 1e3);
    res.measured["slowest_s10"] = {{}, ttc(1.0) > ttc(0.55) && ttc(1.0) > ttc(0.7), note};
    // Wide channel: at the common times 100, 200, 400, 800 ms (fixed before the run), the smaller
    // s*, the higher (closer to the centreline at 25 um); a time at which all three are already
    // within two mesh cells of the centreline cannot order them and is skipped.
    {
      auto wide = [&](double s) -> const Case& { return res.cases.at("wide_" + p.membrane.units + "_" + tag(s)); };
      bool holds = true;
      int compared = 0;
      std::string text;
      for (double t : {0.1, 0.2, 0.4, 0.8}) {
        if (t > p.wide_end + 1e-12) continue;
        const double a = value_at(wide(0.55).t, wide(0.55).y, t), b = value_at(wide(0.7).t, wide(0.7).y, t),
                     c = value_at(wide(1.0).t, wide(1.0).y, t);
        char buf[96];
        std::snprintf(buf, sizeof buf, "%s%.0f ms: %.2f/%.2f/%.2f", text.empty() ? "" : "; ", t * 1e3, a * 1e6, b * 1e6, c * 1e6);
        text += buf;
        const double band = 2 * p.wide_mesh, mid = 25e-6;
        if (std::abs(a - mid) < band && std::abs(b - mid) < band && std::abs(c - mid) < band) continue;
        ++compared;
        holds = holds && a > b && b > c;
      }
      res.measured["wide_ordering"] = {{}, holds && compared > 0, "y (um) for s* = 0.55/0.7/1.0 at " + text};
    }
    if (p.study_only) return res;  // the units evidence needs the other reading's runs
    // The units evidence, side by side at the end of the other reading's run.
    std::ostringstream ev;
    ev << "| s* | reading | y at " << p.other_end * 1e3 << " ms (um) | shape at " << p.other_end * 1e3
       << " ms | rear concavity |\n|---|---|---|---|---|\n";
    for (double s : p.other_swelling_ratios)
      for (const std::string& u : {p.membrane.units, p.other_units}) {
        const Case& c = res.cases.at("narrow_" + u + "_" + tag(s));
        if (!c.failure.empty()) {  // the row says why it has no numbers
          char row[64];
          std::snprintf(row, sizeof row, "| %.2f | %s | run stopped: ", s, u.c_str());
          ev << row << c.failure << " | | |\n";
          continue;
        }
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
