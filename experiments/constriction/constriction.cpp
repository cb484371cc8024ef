#include "constriction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "common/case_runner.hpp"
#include "io/csv.hpp"
#include "mesh/channel_mesh.hpp"
#include "reference/uncertainty.hpp"

namespace rbc::constriction {

namespace fs = std::filesystem;

namespace {

// Is a centroid x1 (m) in the wide part, at least 10 um downstream of the passage's exit and
// 5 um upstream of its entry (the cells there have left the constriction behind)?
bool recovered_region(double x, const Obstacle& block, double L) {
  const double s = image_in_period(x, L);
  const double after = s - block.x[1];  // downstream of the exit (periodic)
  const double a = image_in_period(after, L);
  return a >= 10e-6 && a <= L - (block.x[1] - block.x[0]) - 5e-6;
}

// Error against run time: the experiment's scene (blocks, 12 cells) from rest
// to kConvTime over h and Δt, with both couplings. Semi-implicit: h = 1.25, 0.625, 0.3125 um and
// Δt = 6, 3, 1.5, 0.75 us (the experiment runs at 0.3125 um, 3 us). Explicit: below its
// stability limit (measured from rest: at h = 0.625 um 2e-7 s stops at step 19 with
// the membranes oscillating, 1e-7 s runs; at h = 0.3125 um 1e-7 s stops at step 28, 5e-8 s runs),
// Δt halving from the largest stable step. Reference: the finest explicit run (h = 0.3125 um, the smallest Δt);
// error = RMS over the cells of the distance between centroids at kConvTime (x1 periodic), and
// the relative difference of U_wide. The advection's Q from the straight channel's bound. The
// third scheme, kExtrapolatedKind: the semi-implicit coupling in the extrapolated Lie scheme (the
// scene's incremental form: its second-order form, paper/method/07_second_order_in_time.md), at
// 6 and 3 us only: with the blocks it grows unstable at 1.5 and 0.75 us, cells or none (chapter 7).
using case_runner::kExtrapolatedKind;
struct ConvergenceJob { std::string coupling; double h; std::vector<double> dts; };
const std::vector<ConvergenceJob>& convergence_jobs() {
  static const std::vector<ConvergenceJob> jobs = {{"semi-implicit", 1.25e-6, {6e-6, 3e-6, 1.5e-6, 7.5e-7}},
                                                   {"semi-implicit", 0.625e-6, {6e-6, 3e-6, 1.5e-6, 7.5e-7}},
                                                   {"semi-implicit", 0.3125e-6, {6e-6, 3e-6, 1.5e-6, 7.5e-7}},
                                                   {"explicit", 0.625e-6, {1e-7, 5e-8, 2.5e-8}},
                                                   {"explicit", 0.3125e-6, {5e-8, 2.5e-8}},
                                                   {kExtrapolatedKind, 0.625e-6, {6e-6, 3e-6}},
                                                   {kExtrapolatedKind, 0.3125e-6, {6e-6, 3e-6}}};
  return jobs;
}
std::string convergence_name(const std::string& coupling, double h, double dt) {
  char name[96];
  std::snprintf(name, sizeof name, "%s_h%g_dt%g", coupling.c_str(), h * 1e6, dt);
  return name;
}

// With p.only naming one of its runs, that run alone (no comparison).
void convergence_study(const Params& p, Results& res) {
  const std::string toml = std::string(RBCFLOW_SOURCE_DIR) + "/experiments/constriction/constriction.toml";
  for (const ConvergenceJob& j : convergence_jobs())
    for (double dt : j.dts) {
      if (p.coarse_convergence && j.h < case_runner::kReportConvergenceMinH) continue;
      const std::string name = convergence_name(j.coupling, j.h, dt);
      if (!p.only.empty() && p.only != name) continue;
      char num[160];
      std::snprintf(num, sizeof num, "channel.mesh_size=%.17g", j.h);
      std::vector<std::string> o = {num, "time.coupling=\"" + case_runner::coupling_of(j.coupling) + "\"",
                                    "output.snapshots=[0.0]", "output.fields=false"};
      if (j.coupling == kExtrapolatedKind) o.push_back("time.scheme=\"" + case_runner::scheme_of(j.coupling) + "\"");
      std::snprintf(num, sizeof num, "time.dt=%.17g", dt);
      o.push_back(num);
      std::snprintf(num, sizeof num, "time.end=%.17g", std::round(kConvTime / dt) * dt);
      o.push_back(num);
      std::snprintf(num, sizeof num, "output.every=%.17g", kConvTime / 10);
      o.push_back(num);
      // Q from the straight channel's bound at this h (the scene refuses a Δt above Q times it).
      o.push_back("time.advection_substeps=" + std::to_string(load_scene_file(toml, {o[0]}).advection_substeps_for(dt)));
      Scene sc = load_scene_file(toml, o);
      char src[160];
      std::snprintf(src, sizeof src, "constriction convergence %s h=%g um dt=%g s", j.coupling.c_str(), j.h * 1e6, dt);
      sc.source = src;
      const fs::path out = fs::path(p.out_dir) / "conv" / name;
      ConvergenceRun r;
      r.coupling = j.coupling;
      r.h = j.h;
      r.dt = dt;
      r.substeps = sc.advection_substeps;
      const case_runner::CaseRun run = case_runner::run_or_reuse(
          sc, out.string(), {.threads = p.threads, .progress = p.progress, .resume = p.resume, .reuse = p.reuse || p.collect,
                             .collect = p.collect, .label = "constriction convergence " + name});
      r.failure = run.failure;
      if (r.failure.empty()) {
        const RunSummary& s = run.summary;
        r.steps = s.steps;
        r.wall = s.wall_seconds;
        for (const CellState& c : s.cells) {
          r.x.push_back(c.centroid.x());
          r.y.push_back(c.centroid.y());
        }
        r.u_wide = csv_column((out / "series.csv").string(), "wide_velocity").back();
      }
      res.convergence.push_back(r);
    }
  if (!p.only.empty()) return;
  const ConvergenceRun* ref = nullptr;
  for (const auto& r : res.convergence)
    if (r.coupling == "explicit" && r.failure.empty() && (!ref || r.h < ref->h || (r.h == ref->h && r.dt < ref->dt))) ref = &r;
  if (!ref) return;
  const std::size_t ref_index = std::size_t(ref - res.convergence.data());  // (kept by index: runs are added below)
  const double L = 120e-6;
  auto centroids = [](const ConvergenceRun& r) {
    std::vector<Eigen::Vector2d> c;
    for (std::size_t k = 0; k < r.x.size(); ++k) c.emplace_back(r.x[k], r.y[k]);
    return c;
  };
  // Richardson extrapolation in Δt (first order) of each pair Δt, 2Δt of a coupling and h that both
  // finished: the centroids 2 c(Δt) − c(2Δt), U_wide likewise, at the cost of both runs (kind
  // "<coupling> Richardson").
  std::vector<ConvergenceRun> extrapolated;
  for (const auto& fine : res.convergence)
    for (const auto& coarse : res.convergence)
      if (&fine != ref && fine.coupling != kExtrapolatedKind && coarse.coupling == fine.coupling &&
          case_runner::halving_pair(fine.h, fine.dt, coarse.h, coarse.dt) &&
          fine.failure.empty() && coarse.failure.empty()) {
        ConvergenceRun r = fine;
        r.coupling = fine.coupling + " Richardson";
        r.steps = fine.steps + coarse.steps;
        r.wall = fine.wall + coarse.wall;
        r.x.clear();
        r.y.clear();
        for (const Eigen::Vector2d& c : case_runner::richardson_centroids(centroids(fine), centroids(coarse), L)) {
          r.x.push_back(c.x());
          r.y.push_back(c.y());
        }
        r.u_wide = richardson_extrapolate(fine.u_wide, coarse.u_wide, 2, 1);
        extrapolated.push_back(r);
      }
  res.convergence.insert(res.convergence.end(), extrapolated.begin(), extrapolated.end());
  ref = &res.convergence[ref_index];
  for (auto& r : res.convergence) {
    if (!r.failure.empty()) continue;
    r.error = case_runner::centroid_error(centroids(r), centroids(*ref), L).first;  // RMS over the cells
    r.u_error = std::abs(r.u_wide - ref->u_wide) / ref->u_wide;
  }
  std::ofstream csv(fs::path(p.out_dir) / "convergence.csv");
  csv << "coupling,h_um,dt_s,substeps,steps,wall_seconds,u_wide_cm_s,error_um,u_error,failure\n";
  for (const auto& r : res.convergence)
    csv << r.coupling << "," << r.h * 1e6 << "," << r.dt << "," << r.substeps << "," << r.steps << "," << r.wall << ","
        << r.u_wide * 100 << "," << (r.failure.empty() ? r.error * 1e6 : NAN) << "," << (r.failure.empty() ? r.u_error : NAN) << ","
        << (r.failure.empty() ? "" : "stopped") << "\n";
  std::ostringstream md;
  md << "Error against run time (the experiment's scene with its blocks and 12 cells, from rest to t = " << kConvTime * 1e3
     << " ms): RMS over the cells of the centroid distance to the finest run (explicit, h = " << ref->h * 1e6 << " um, Δt = " << ref->dt
     << " s), and the relative difference of U_wide at that time; wall time of each run (" << (p.threads ? std::to_string(p.threads) : "all")
     << " threads, one run after the other). Errors below the reference's own (unknown) error are not resolved: the h-error of "
        "the reference's h is not in it. Rows \"Richardson\": 2 c(Δt) − c(2Δt) from the runs at Δt and 2Δt of the same coupling "
        "and h, at the wall time of both (none from the reference itself; Q is the finer run's: where the coarser run took twice as "
        "many advection substeps, their common substep's error is carried, not extrapolated). Rows \"" << kExtrapolatedKind << "\": the "
        "semi-implicit coupling in the extrapolated Lie scheme (each step 2 L_{Δt/2}² − L_Δt).\n\n";
  md << "| coupling | h (um) | Δt (s) | Q | steps | wall (s) | U_wide (cm/s) | centroid error (um) | U_wide error | observed order in Δt |\n"
        "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& coupling : {std::string("semi-implicit"), std::string("semi-implicit Richardson"), kExtrapolatedKind,
                                      std::string("explicit"), std::string("explicit Richardson")})
    for (double h : {1.25e-6, 0.625e-6, 0.3125e-6}) {
      std::vector<const ConvergenceRun*> runs;
      for (const auto& r : res.convergence)
        if (r.coupling == coupling && r.h == h) runs.push_back(&r);
      std::sort(runs.begin(), runs.end(), [](auto* a, auto* b) { return a->dt > b->dt; });
      for (std::size_t k = 0; k < runs.size(); ++k) {
        const ConvergenceRun& r = *runs[k];
        // Observed Δt order at fixed h, from three successive runs (Δt halving): log2 of the ratio
        // of the RMS centroid differences between neighbours.
        std::string order;
        if (k >= 2 && runs[k - 2]->failure.empty() && runs[k - 1]->failure.empty() && r.failure.empty()) {
          auto dist = [&](const ConvergenceRun& a, const ConvergenceRun& b) {
            return case_runner::centroid_error(centroids(a), centroids(b), L).first;
          };
          const double d1 = dist(*runs[k - 2], *runs[k - 1]), d2 = dist(*runs[k - 1], r);
          if (d2 > 0) order = std::to_string(std::log2(d1 / d2)).substr(0, 4);
        }
        char row[320];
        if (r.failure.empty())
          std::snprintf(row, sizeof row, "| %s | %g | %.3g | %d | %ld | %.1f | %.5f | %.2e | %.1e | %s |\n", coupling.c_str(), h * 1e6, r.dt,
                        r.substeps, r.steps, r.wall, r.u_wide * 100, r.error * 1e6, r.u_error, order.c_str());
        else
          std::snprintf(row, sizeof row, "| %s | %g | %.3g | %d | - | - | - | stopped: %.120s | - | |\n", coupling.c_str(), h * 1e6, r.dt,
                        r.substeps, r.failure.c_str());
        md << row;
      }
    }
  // Observed h order: the smallest Δt of each h, semi-implicit (the explicit runs have two h).
  std::vector<const ConvergenceRun*> finest;
  for (double h : {1.25e-6, 0.625e-6, 0.3125e-6}) {
    const ConvergenceRun* best = nullptr;
    for (const auto& r : res.convergence)
      if (r.coupling == "semi-implicit" && r.h == h && r.failure.empty() && (!best || r.dt < best->dt)) best = &r;
    if (best) finest.push_back(best);
  }
  if (finest.size() == 3) {
    auto du = [](const ConvergenceRun* a, const ConvergenceRun* b) { return std::abs(a->u_wide - b->u_wide); };
    md << "\nObserved order in h (semi-implicit, Δt = " << finest[2]->dt << " s, h = 1.25, 0.625, 0.3125 um) of U_wide at "
       << kConvTime * 1e3 << " ms: " << std::log2(du(finest[0], finest[1]) / du(finest[1], finest[2])) << ".\n";
  }
  std::ofstream(fs::path(p.out_dir) / "convergence.md") << md.str();
}

}  // namespace

std::vector<std::string> cases(const Params& p) {
  std::vector<std::string> names{kMainRun};
  if (!p.quick && p.convergence)
    for (const ConvergenceJob& j : convergence_jobs())
      for (double dt : j.dts)
        if (!p.coarse_convergence || j.h >= case_runner::kReportConvergenceMinH) names.push_back(convergence_name(j.coupling, j.h, dt));
  return names;
}

Results run(const Params& p) {
  Results res;
  if (!p.only.empty()) {  // one case alone, no comparison
    case_runner::require_case(cases(p), p.only, "constriction");
    if (p.only != kMainRun) {
      convergence_study(p, res);
      return res;
    }
  }
  std::vector<std::string> overrides;
  if (p.quick) overrides = {"channel.mesh_size=0.625e-6", "time.end=" + std::to_string(kQuickEnd), "output.every=5e-5",
                            "output.snapshots=[0.0, 1e-3, 2e-3]"};
  const Scene scene = load_scene_file(std::string(RBCFLOW_SOURCE_DIR) + "/experiments/constriction/constriction.toml", overrides);
  const fs::path out = fs::path(p.out_dir) / "run";
  const std::optional<RunSummary> done = p.reuse || p.collect ? read_finished_run(out.string(), scene) : std::nullopt;
  if (done) {
    res.summary = *done;
  } else if (p.collect) {  // nothing to read back: the comparison says "not run" for its rows
    res.collected_without_run = true;
    if (p.only.empty() && !p.quick && p.convergence) convergence_study(p, res);
    return res;
  } else {
    const bool resume = p.resume && has_checkpoint(out.string());
    res.summary = run_scene(scene, {.out_dir = out.string(), .threads = p.threads, .progress = p.progress, .label = "constriction",
                                    .checkpoint_wall = 300, .resume = resume});
  }
  if (!p.only.empty()) return res;

  // The rows, from series.csv (samples every output.every).
  const std::string series = (out / "series.csv").string();
  const auto t = csv_column(series, "t"), wide = csv_column(series, "wide_velocity"), narrow = csv_column(series, "narrow_velocity");
  const auto hct = csv_column(series, "hematocrit");
  res.window_start = p.quick ? kQuickEnd / 2 : kWindowStart;
  res.window_end = t.back();
  int n = 0;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= res.window_start - 1e-12) {
      res.u_wide += wide[k];
      res.u_narrow += narrow[k];
      ++n;
    }
  res.u_wide /= n;
  res.u_narrow /= n;
  const double rho = scene.fluid.density, mu = scene.fluid.viscosity;
  const Obstacle& block = scene.obstacles.front();
  const double H = scene.height, Hn = H - 2 * (block.y[1] - block.y[0]);
  res.re_wide = rho * res.u_wide * H / mu;
  res.re_narrow = rho * res.u_narrow * Hn / mu;
  res.hematocrit = hct.front();

  // Toward the centre: mean |y − H/2| of the cells at t = 0, when the leading cell's centroid
  // first reaches the passage's entry, and over the window.
  const std::size_t ncells = scene.cells.size();
  std::vector<std::vector<double>> cx(ncells), cy(ncells);
  for (std::size_t c = 0; c < ncells; ++c) {
    cx[c] = csv_column(series, "cell" + std::to_string(c) + "_x");
    cy[c] = csv_column(series, "cell" + std::to_string(c) + "_y");
  }
  auto offset = [&](std::size_t k) {
    double s = 0;
    for (std::size_t c = 0; c < ncells; ++c) s += std::abs(cy[c][k] - H / 2);
    return s / ncells;
  };
  res.offset_start = offset(0);
  std::size_t entry = t.size() - 1;
  for (std::size_t k = 0; k < t.size() && entry == t.size() - 1; ++k)
    for (std::size_t c = 0; c < ncells; ++c)
      if (cx[c][k] >= block.x[0]) { entry = k; break; }
  res.entry_time = t[entry];
  res.offset_entry = offset(entry);
  double late = 0;
  int nl = 0;
  for (std::size_t k = 0; k < t.size(); ++k)
    if (t[k] >= res.window_start - 1e-12) { late += offset(k); ++nl; }
  res.offset_late = late / nl;

  // Shape memory: the cells that have left the passage (centroid 10 um or more past its exit, not
  // yet at the next entry) at the end, biconcave in their own frame (cell_diagnostics.hpp: both
  // faces dimpled, both ends convex, however the cell is tilted); every prepared cell is. The
  // flow-frame descriptor is counted too: it calls a tilted biconcave cell "other" (the first full
  // run,: 0 of 7 by it, the cells tilted by 20-45 degrees, see README.md).
  for (const CellState& c : res.summary.cells)
    if (recovered_region(c.centroid.x(), block, scene.length)) {
      ++res.wide_cells_end;
      if (c.own_frame.biconcave) ++res.biconcave_end;
      if (c.shape.kind == "biconcave") ++res.biconcave_flow_frame_end;
      res.tilt_end.push_back(c.own_frame.angle * 180 / 3.141592653589793);
    }

  // Time series for Fig. 13 (centroid heights, um) and the mean velocities.
  {
    std::ofstream f(fs::path(p.out_dir) / "centroids.dat");
    f << "# t (ms), then x2 of each cell's centroid (um)\n";
    for (std::size_t k = 0; k < t.size(); ++k) {
      f << t[k] * 1e3;
      for (std::size_t c = 0; c < ncells; ++c) f << " " << cy[c][k] * 1e6;
      f << "\n";
    }
  }

  std::ostringstream window;
  window << "over " << res.window_start * 1e3 << "-" << res.window_end * 1e3 << " ms (" << n << " samples)";
  res.measured["hct"] = {res.hematocrit, {}, "12 cells over L H minus the blocks, at t = 0"};
  if (p.quick) {  // the quick case's flow rows are checked against its regression record only
    res.measured.erase("hct");
    res.measured["hct"] = {res.hematocrit, {}, "12 cells over L H minus the blocks, at t = 0 (geometry: the quick mesh)"};
  }
  if (!p.quick) res.measured["u_wide"] = {res.u_wide * 100, {}, window.str()};
  if (!p.quick) res.measured["u_narrow"] = {res.u_narrow * 100, {}, window.str() + "; U_narrow/U_wide = " + std::to_string(res.u_narrow / res.u_wide)};
  if (!p.quick) res.measured["re_wide"] = {res.re_wide, {}, "H = 30 um"};
  if (!p.quick) res.measured["re_narrow"] = {res.re_narrow, {}, "H = 15 um"};
  if (!p.quick) {
    // The four rows under each reading of U (reference-data/readings.csv), over the same window:
    // the flux over the open height (the rows' own) and the nodal mean over the open passage with
    // its bounding rows. The plasma readings are not measured part by part.
    const double u_wide_nodal = case_runner::window_mean(t, csv_column(series, "wide_nodal_velocity"), res.window_start),
                 u_narrow_nodal = case_runner::window_mean(t, csv_column(series, "narrow_nodal_velocity"), res.window_start);
    auto readings = [](double p1, double nodal) {
      std::vector<std::pair<std::string, double>> r;
      for (const auto& [id, v] : {std::pair{"p1_mean", p1}, std::pair{"nodal_mean", nodal}})
        if (std::isfinite(v)) r.emplace_back(id, v);
      return r;
    };
    res.measured["u_wide"].readings = readings(res.u_wide * 100, u_wide_nodal * 100);
    res.measured["u_narrow"].readings = readings(res.u_narrow * 100, u_narrow_nodal * 100);
    res.measured["re_wide"].readings = readings(res.re_wide, rho * u_wide_nodal * H / mu);
    res.measured["re_narrow"].readings = readings(res.re_narrow, rho * u_narrow_nodal * Hn / mu);
  }
  {
    std::ostringstream s;
    s.precision(3);
    s << "mean |y - H/2| " << res.offset_start * 1e6 << " um at t = 0, " << res.offset_entry * 1e6 << " um when the leading cell reaches the passage ("
      << res.entry_time * 1e3 << " ms), " << res.offset_late * 1e6 << " um " << window.str();
    if (!p.quick) res.measured["toward_centre"] = {{}, res.offset_entry < res.offset_start && res.offset_late < res.offset_start, s.str()};
  }
  {
    std::ostringstream s;
    s.precision(2);
    s << std::fixed << res.biconcave_end << " of the " << res.wide_cells_end << " cells 10 um or more past the passage at "
      << res.window_end * 1e3 << " ms are biconcave in their own frame (all 12 at t = 0); tilts of their long axes";
    for (double a : res.tilt_end) s << " " << std::setprecision(0) << a;
    s << " degrees; by the first criterion, the flow-frame descriptor, " << res.biconcave_flow_frame_end << " (it calls a tilted one other): "
      << (res.wide_cells_end > 0 && res.biconcave_flow_frame_end == res.wide_cells_end ? "holds" : "does not hold");
    if (!p.quick) res.measured["shape_memory"] = {{}, res.wide_cells_end > 0 && res.biconcave_end == res.wide_cells_end, s.str()};
  }
  if (!p.quick && p.convergence) convergence_study(p, res);
  if (!p.quick) {
    // u_num of the flow rows: the window's part (the spread of the means of its five
    // fifths) and the Δt part, relative, from the convergence runs at the row's h and coupling
    // (U_wide at 1 ms with Δt = 3, 1.5, 0.75 us: a proxy on a short horizon, first order).
    const double span = (res.window_end - res.window_start) / 5;
    std::optional<RefinementUncertainty> dt_rel;
    {
      std::map<double, double> at;  // Δt -> U_wide at kConvTime
      for (const ConvergenceRun& r : res.convergence)
        if (r.failure.empty() && r.coupling == scene.coupling && std::abs(r.h - scene.mesh_size) < 1e-12 && r.dt <= scene.dt * 1.0001)
          at[r.dt] = r.u_wide;
      std::vector<double> seq;
      for (const auto& [dt, u] : at) seq.push_back(u / at.rbegin()->second);  // finest first, relative to the row's Δt
      if (seq.size() >= 2) {
        // The row's own Δt is the coarsest level: its U, from it and the (at most) two finer ones.
        if (seq.size() > 3) seq.erase(seq.begin(), seq.end() - 3);
        dt_rel = grid_convergence_index(seq, 2.0, 1.0, int(seq.size()) - 1);
        dt_rel->label = "dt (relative, at 1 ms, from the convergence runs)";
      }
    }
    auto fill = [&](const std::string& id, const std::vector<double>& v, double scale) {
      Measured& m = res.measured[id];
      m.u.window = window_noise(t, v, span, 5) * scale;
      if (dt_rel) {
        RefinementUncertainty d = *dt_rel;  // in the row's unit
        d.u *= *m.value;
        d.extrapolated *= *m.value;
        for (double& level : d.values) level *= *m.value;
        m.u.dt = d;
      } else {
        m.u.missing = "the convergence runs' Δt sequence";
      }
      char how[240];
      std::snprintf(how, sizeof how, "%s coupling%s, dt = %g us, h = %g um; incremental pressure form (not the study's); area term (7) during the flow",
                    scene.coupling.c_str(), scene.coupling == "explicit" ? "" : " (not the study's explicit one)", scene.dt * 1e6, scene.mesh_size * 1e6);
      m.how = how;
    };
    fill("u_wide", wide, 100);
    fill("u_narrow", narrow, 100);
    fill("re_wide", wide, rho * H / mu);
    fill("re_narrow", narrow, rho * Hn / mu);
  }
  {
    Measured& m = res.measured["hct"];
    m.u.other = "geometry of the prepared cells (round-off)";
    m.u.other_value = 0.0;
    m.how = "the prepared cells' areas over the fluid area (geometry)";
  }
  if (p.quick) {
    res.quick_record["u_wide"] = {"mean velocity, wide part, 1-2 ms", "cm/s", res.u_wide * 100};
    res.quick_record["u_narrow"] = {"mean velocity, narrow part, 1-2 ms", "cm/s", res.u_narrow * 100};
    res.quick_record["hct"] = {"hematocrit at t = 0", "%", res.hematocrit};
    res.quick_record["offset_end"] = {"mean |y - H/2| of the cells at the end", "um", offset(t.size() - 1) * 1e6};
    for (std::size_t c = 0; c < ncells; ++c) {
      res.quick_record["cell" + std::to_string(c) + "_x"] = {"cell " + std::to_string(c) + " centroid x1 at the end", "um", cx[c].back() * 1e6};
      res.quick_record["cell" + std::to_string(c) + "_y"] = {"cell " + std::to_string(c) + " centroid x2 at the end", "um", cy[c].back() * 1e6};
    }
  }
  return res;
}

}  // namespace rbc::constriction
