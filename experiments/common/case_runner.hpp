#pragma once
// What the experiments made of independent cases share: every case is one
// scene run in its own folder, so that GNU parallel or a Slurm array can run the cases anywhere
// (--list-cases, --only NAME) and the experiment collects them afterwards (--check --reuse).
//
//   run_or_reuse   runs the case's scene into its folder, or with reuse reads back the finished
//                  run of the same scene (summary.json) or the failure it stopped with
//                  (failure.txt: the scene's source, its Δt, then why), so that a collecting
//                  --check --reuse neither reruns a finished case nor a failed one;
//   window_mean    the mean of a sampled series over t ≥ from (the rows' "last millisecond");
//   value_at       a series at a common instant, between its samples (curves compared over time);
//   symmetric_unit a uniform number in [−1, 1) from a Mersenne twister's raw 32-bit output (the
//                  same on every platform, unlike std::uniform_real_distribution): the ensembles'
//                  perturbed starts;
//   num            a number written back exactly (%.17g) into a scene override;
//   run_selected   runs an experiment's cases (or only the one --only names) one after the other;
//   centroid_error, convergence_table
//                  the work-precision study (error against run time): the RMS distance of the
//                  bodies' centroids from a reference run's, and the table and csv of the runs.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "scene/run_scene.hpp"

namespace rbc::case_runner {

struct CaseRun {
  RunSummary summary;
  std::string failure;  // why the run stopped (one line; empty: it reached its end)
  std::string code;     // the code that made a run read back from the evidence kept in the
                        // repository (its folder's code_id, paper/keep_evidence.sh); empty: this code
};

struct CaseRunOptions {
  int threads = 0;
  bool progress = true;
  bool resume = false;  // continue from the folder's checkpoint, if there is one
  bool reuse = false;   // read a finished (or failed) run of the same scene back
  bool collect = false; // with reuse: never run; a case not finished (nor failed) is kNotRun
  std::string label;    // the progress line's name
};

// make reproduce's error against run time: an experiment's convergence runs on its coarse meshes
// (h of 0.625 um and up), a few core-minutes against the hours of the finer h that make evidence
// adds; the reference is then the explicit run at the finest h present and the smallest Δt.
inline constexpr double kReportConvergenceMinH = 0.6e-6;  // m
inline bool in_report_convergence(const std::string& role, double h) { return role == "convergence" && h >= kReportConvergenceMinH; }

// The failure of a case that --collect found neither finished nor stopped (still running elsewhere,
// or not started): left out of the experiment's tables, which say "not run".
inline const std::string kNotRun = "not run (--collect)";

// Throws what run_scene throws except RunFailure (returned as the failure).
CaseRun run_or_reuse(const Scene& scene, const std::string& out_dir, const CaseRunOptions& o);

double window_mean(const std::vector<double>& t, const std::vector<double>& v, double from);
// A sampled series v(t) at the instant `at`, s, linearly between the two samples around it (a
// run samples at the first step at or past each interval, and kept series are thinned: curves are
// compared at common instants); NaN outside [t.front(), t.back()].
double value_at(const std::vector<double>& t, const std::vector<double>& v, double at);

// A row's value under each reading of U, "the averaged velocity in the channel" (the study's
// Section 2; reference-data/readings.csv), from a run's series.csv: the window_mean over t ≥ from of
// each reading's column times `scale` (ρH/μ for a Reynolds number, 100 for cm/s): p1_mean
// (mean_velocity), nodal_mean (nodal_mean_velocity) and, with cells, plasma_flux
// (plasma_flux_velocity) and plasma_open (plasma_open_velocity). Columns a series lacks, and
// windows with no sample, give no reading (a cell-free run has no plasma readings).
std::vector<std::pair<std::string, double>> u_readings(const std::string& series, double from, double scale);
double symmetric_unit(std::mt19937& g);
std::string num(double v);

// RMS over the bodies of |c − ref| (x1 to the nearest periodic image, channel length L) and of its
// x2 part; a and ref hold the same bodies in the same order. Returns {total, x2}.
std::pair<double, double> centroid_error(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& ref, double L);

// Two runs a Richardson extrapolation in Δt combines: the same h (m), the coarse Δt twice the fine (s).
inline bool halving_pair(double fine_h, double fine_dt, double coarse_h, double coarse_dt) {
  return coarse_h == fine_h && std::abs(coarse_dt / fine_dt - 2) < 1e-9;
}
// Richardson extrapolation in Δt (first order) of the bodies' centroids from runs at Δt (fine) and
// 2Δt (coarse): 2 c(Δt) − c(2Δt) body by body, the coarse x1 taken to the image nearest the fine
// one (channel length L); fine and coarse hold the same bodies in the same order.
std::vector<Eigen::Vector2d> richardson_centroids(const std::vector<Eigen::Vector2d>& fine, const std::vector<Eigen::Vector2d>& coarse,
                                                  double L);

// The schemes a work-precision diagram or the stability map compares, each by one label (its kind):
// "explicit" and "semi-implicit", the study's Lie scheme with that [time] coupling, and
// kExtrapolatedKind, the semi-implicit coupling in the extrapolated Lie scheme ([time] scheme =
// "lie-extrapolated", paper/method/07_second_order_in_time.md).
inline const std::string kExtrapolatedKind = "semi-implicit-extrapolated";
// A kind's [time] coupling and scheme, and a run's kind from them.
inline std::string coupling_of(const std::string& kind) { return kind == kExtrapolatedKind ? "semi-implicit" : kind; }
inline std::string scheme_of(const std::string& kind) { return kind == kExtrapolatedKind ? "lie-extrapolated" : "lie"; }
inline std::string kind_of(const std::string& coupling, const std::string& scheme) {
  return scheme == "lie-extrapolated" ? kExtrapolatedKind : coupling;
}
// A kind as the work-precision runs' case names abbreviate it: "si", "sie", else the kind itself.
inline std::string short_kind(const std::string& kind) {
  return kind == "semi-implicit" ? "si" : kind == kExtrapolatedKind ? "sie" : kind;
}

// One run of a work-precision study: its kind ("explicit", "semi-implicit", ...), h (m), Δt (s),
// steps, wall time (s), errors (m; NaN without a reference) and why it stopped (empty: it did not).
struct ConvergenceRow {
  std::string kind;
  double h = 0, dt = 0;
  long steps = 0;
  double wall_seconds = 0, error = NAN, x2_error = NAN;
  std::string failure;
};
// Writes csv_path (kind,h_um,dt_s,steps,wall_seconds,error_um,lateral_error_um,failure: plot.gp's
// work-precision figure) and returns the markdown table, after `intro`, sorted by kind, h and Δt.
std::string convergence_table(std::vector<ConvergenceRow> rows, const std::string& csv_path, const std::string& intro);

// --only NAME where NAME is none of the experiment's cases: an error pointing to its --list-cases.
inline void require_case(const std::vector<std::string>& names, const std::string& only, const std::string& experiment) {
  if (!only.empty() && std::find(names.begin(), names.end(), only) == names.end())
    throw std::invalid_argument("--only " + only + ": no such case (build/bin/" + experiment + " --list-cases lists them)");
}

// Runs every case of `all` (or only the one named `only`; an unknown name is an error pointing to
// the experiment's --list-cases) with run_case, after creating out_dir; the results by case name.
template <class Case, class RunCase>
auto run_selected(std::vector<Case> all, const std::string& only, const std::string& experiment, const std::string& out_dir,
                  RunCase run_case) {
  if (!only.empty()) {
    std::vector<std::string> names;
    for (const Case& c : all) names.push_back(c.name);
    require_case(names, only, experiment);
    std::erase_if(all, [&](const Case& c) { return c.name != only; });
  }
  std::filesystem::create_directories(out_dir);
  std::map<std::string, decltype(run_case(all.front()))> results;
  for (const Case& c : all) results[c.name] = run_case(c);
  return results;
}

}  // namespace rbc::case_runner
