#pragma once
// Experiment single_cell_migration — one red blood cell in plane Poiseuille flow
// (Shi, Pan & Glowinski 2012, DOI 10.1002/fld.2455, Section 3.1.1, Figures 3, 4 and 5).
//
// Claim: in the narrow channel (20 × 10 µm, h = 0.125 µm, Re0 = 0.5556) a cell released at
// (5, 3) µm migrates to the centreline within a few ms; cells with s* = 0.55 and 0.7 take
// parachute shapes, s* = 1 a slightly bullet-like one and is the slowest. Hct = 6.77, 8.62,
// 12.32 % and Re with the cell 0.5176, 0.5023, 0.5028. In the wide channel (100 × 50 µm,
// h = 0.3125 µm) the ordering reverses: the smaller s*, the faster toward the centreline.
// Also: which reading of the study's 2D constants (paper/method/02_membrane.md) gives this behaviour.
//
// Run:  build/bin/single_cell_migration --check          (about 1 h on 2 cores; see README.md)
//       build/bin/single_cell_migration --quick --check  (h = 0.25 um, to 1 ms; under a minute)
#include <map>
#include <string>
#include <vector>

#include "reference/reference_table.hpp"
#include "reference/regression_record.hpp"
#include "scene/run_scene.hpp"

namespace rbc::single_cell_migration {

struct Params {
  std::string out_dir = "results/single_cell_migration";
  bool quick = false;
  int threads = 0;  // OpenMP threads of each case (0: every core); the cases run one after the other
  bool progress = true;

  // The study's parameters (Section 3.1.1) and our choices where it is silent.
  std::vector<double> swelling_ratios = {0.55, 0.7, 1.0};
  // k_l, k_b, k_s as the study gives them and their reading in 2D (units: chosen by the evidence
  // below, README.md); the experiment's cases all use these.
  MembraneConstants membrane;  // units = "si" (MembraneConstants default)
  double narrow_mesh = 0.125e-6;   // h, m (80 per 10 um)
  double narrow_dt = 2e-8;         // s; below the explicit limit at this h (paper/method/03_immersed_boundary.md)
  double narrow_end = 7.5e-3;      // s
  double sample_every = 5e-5;      // s; Re with the cell is averaged over the last sample interval
  // Units evidence: the other reading run over the first part of the migration.
  std::string other_units = "cgs";
  double other_dt = 1.2e-9;        // s; the CGS reading is ~25x stiffer in time step
  double other_end = 1.0e-3;       // s
  std::vector<double> other_swelling_ratios = {0.55, 1.0};  // a parachute and a bullet in the study
  // Wide channel (Figure 5): initial centroid (25, 10) um (not stated in the study: our choice).
  // The study's 800 ms with the semi-implicit coupling at Δt = 6e-6 s: 75 times our explicit
  // limit at this h (8e-8 s), Q = 4 wave-like substeps for the advective bound (6.25e-6 s);
  // chosen so that the three runs fit in one working session (≈ 1 h on 2 cores). Its Δt error,
  // measured on the first 2 ms against the explicit scheme (Δt = 5e-8 s): the lateral
  // displacement of the centroid is 9 % (2e-6 s) and 22 % (6e-6 s) short.
  double wide_mesh = 0.3125e-6;    // m (32 per 10 um)
  std::string wide_coupling = "semi-implicit";
  double wide_dt = 6e-6;           // s
  int wide_substeps = 4;           // Q
  double wide_end = 0.8;           // s, as in the study
  double wide_every = 5e-4;        // s between samples
  double wide_y0 = 10e-6;          // m
  // Re with the cell against h and Δt: the narrow runs again at h = 0.5 and 0.25 um,
  // and at 0.25 um with Δt halved, to 7.5 ms (explicit; each Δt ~60 % of that h's stable limit).
  bool re_convergence = true;
  std::vector<std::pair<double, double>> re_runs = {{0.5e-6, 8e-8}, {0.25e-6, 4e-8}, {0.25e-6, 2e-8}};  // (h m, Δt s)
  double re_window = 1e-3;  // s: Re also averaged over the last re_window of the run (the evidence table)
  // Error against run time: the narrow channel on a short horizon, s* = 0.55, both
  // couplings over h and Δt, and the semi-implicit one in the extrapolated Lie scheme with the
  // incremental form of the pressure (its second-order form: paper/method/07_second_order_in_time.md);
  // the error of the centroid height at conv_time against the finest run (explicit, h = 0.125 µm,
  // Δt = 6e-9 s). Each Δt list halves, for the observed orders.
  bool convergence = true;
  double conv_time = 2.5e-4;  // s
  std::map<double, std::vector<double>> conv_explicit = {
      {0.5e-6, {1.2e-7, 6e-8, 3e-8}}, {0.25e-6, {6e-8, 3e-8, 1.5e-8}}, {0.125e-6, {2.4e-8, 1.2e-8, 6e-9}}};
  std::map<double, std::vector<double>> conv_semi_implicit = {
      {0.5e-6, {1.6e-6, 8e-7, 4e-7, 2e-7}}, {0.25e-6, {8e-7, 4e-7, 2e-7, 1e-7}}, {0.125e-6, {8e-7, 4e-7, 2e-7, 1e-7}}};
  std::map<double, std::vector<double>> conv_extrapolated = {{0.125e-6, {1.6e-6, 8e-7, 4e-7, 2e-7}}};
  // Running a part: only the case named `only` (a name from case_names), or the cases whose name
  // starts with it ("wide", "narrow_si", …), and
  // reuse: a case whose output folder holds a finished run of the same scene is read, not rerun.
  std::string only;
  bool reuse = false;
  // collect: with reuse, run none; a case neither finished nor failed is "not run" (make evidence
  // COLLECT=1, a sweep still going elsewhere).
  bool collect = false;
  // study_only: the runs the study's rows and figures read (the narrow and wide channels under the
  // chosen reading), none of the evidence (make reproduce: u_num as recorded by make evidence,
  // reference/recorded_uncertainty.hpp). The quick parameters have only those.
  bool study_only = false;
  // resume: a case whose folder holds a checkpoint (a run stopped by SIGINT/SIGTERM) continues
  // from it. SIGINT/SIGTERM stop every running case after its checkpoint (RunInterrupted).
  bool resume = false;
  // Checks.
  double centreline_band = 0.25e-6;  // |y − H/2| that counts as "on the centreline", m (2 mesh cells)
  double centreline_check_time = 7e-3;  // s (Figure 4's axis ends at 7 ms)

  static Params quick_params();  // h = 0.25 um, Δt = 4e-8 s, to 1 ms; no evidence or wide runs
};

struct Case {
  std::string name;        // e.g. "narrow_si_s055"
  double swelling_ratio = 1;
  std::string units;
  RunSummary summary;
  std::vector<double> t, y;  // centroid height history, s and m
  double hematocrit0 = 0;    // % at t = 0 (the prepared cell)
  double time_to_centreline = -1;  // s, first time |y − H/2| < band; −1 if never
  std::string failure;       // non-empty if the run stopped (instability): the cause
};

struct ConvergenceRun {
  std::string coupling;
  double h = 0, dt = 0;  // m, s
  long steps = 0;
  double wall_seconds = 0, y = 0, error = 0;  // s, m, m (|y − y_reference|)
};

struct Results {
  std::map<std::string, Case> cases;
  std::vector<ConvergenceRun> convergence;
  std::string convergence_summary;  // Markdown: reference, observed orders
  std::map<std::string, Measured> measured;  // ids of reference-data/single_cell_migration.csv
  std::string units_evidence;                // a short paragraph for the report
  std::string re_evidence;                   // Markdown: Re against h, Δt, averaging window, definition
  // Quick runs: the quick case's own numbers, for its regression record (reference-data/regression/).
  std::map<std::string, Observed> quick_record;
};

Results run(const Params& params);
// The names of the cases run(params) runs, the longest first (--list-cases, for GNU parallel).
std::vector<std::string> case_names(const Params& params);

}  // namespace rbc::single_cell_migration
