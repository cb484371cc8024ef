#pragma once
// stability_map — the largest stable time step of the couplings and schemes (ours: the study has no such test).
//
// Question: how does the stable Δt depend on the membrane stiffness (k_l × 0.01 … 100,
// k_b × 1 … 1000) and on the mesh size h, for the study's explicit coupling and for our
// semi-implicit one, in the study's Lie scheme and (the semi-implicit one) in its second-order
// extrapolation; and do the extreme cases run (1000 k_b, 10–100 k_l, Hct 34 %, a cell one mesh
// cell from a wall, s* = 0.481 through the 15 µm passage, Re0 from 0.01 to 50)?
//
// Set-up (our choice; the study has no such test): the narrow channel (20 × 10 µm, Re0 = 0.5556),
// one s* = 0.55 cell released at (5, 3) µm, SI reading of the constants. A Δt counts as stable if
// kSteps steps (and at least kMinTime of flow) run without the health check stopping the run
// (non-finite values, CFL > 1, spring strain > 1, a node through a wall). Bisection in log Δt
// between a stable and an unstable value until their ratio is below kRatio; the search stops at
// the advective cap Δt_adv (the wave-like step's bound with Q = kMaxSubsteps), which the flow
// itself sets: "≥ cap" means stable there.
#include <map>
#include <string>
#include <vector>

#include "common/case_runner.hpp"
#include "reference/regression_record.hpp"

namespace rbc::stability_map {

struct Params {
  std::string out_dir = "results/stability_map";
  bool quick = false;
  bool progress = true;
  // the schemes compared (case_runner's kinds: the extrapolated one is the semi-implicit coupling
  // in the extrapolated Lie scheme)
  std::vector<std::string> couplings = {"explicit", "semi-implicit", case_runner::kExtrapolatedKind};
  std::vector<double> mesh_sizes = {0.5e-6, 0.25e-6, 0.125e-6};  // h, m
  std::vector<double> kl_scales = {0.01, 0.1, 1, 10, 100};       // k_l / 5e-8, with k_b × 1
  std::vector<double> kb_scales = {10, 100, 1000};                // k_b / 5e-10, with k_l × 1
  int steps = 400;            // steps per trial
  double min_time = 2e-5;     // s of flow per trial at least (small Δt)
  double ratio = 1.15;        // bisection ends when unstable/stable < ratio
  int max_substeps = 4;       // Q at the cap
  bool reuse = false;         // read a finished map from out_dir instead of recomputing it
  bool resume = false;        // keep the points a stopped map already wrote, compute the rest
  bool collect = false;       // read the points and extreme cases already written, compute none
  std::string only;           // compute only this case (a name of cases())
  static Params quick_params();   // h = 0.5, 0.25 um; k_l × 0.1, 1, 10; k_b × 1000; the two couplings' Lie scheme
  static Params report_params();  // make reproduce's map: h = 0.5 and 0.25 um (h and h halved), every
                                  // stiffness and extreme case (make evidence adds h = 0.125 um)
};

struct Point {
  std::string coupling;
  double h = 0, kl_scale = 1, kb_scale = 1;
  double stable = 0, unstable = 0;  // s; unstable = 0: stable at the cap
  double cap = 0;                   // s, the advective cap
  std::string cause;                // of the smallest unstable trial
  int trials = 0;
};

struct Extreme {
  std::string name, what, coupling;
  double dt = 0, end = 0;
  bool stable = false;
  std::string outcome;  // "ran to t = …" or the failure
  double wall_seconds = 0;
};

struct Results {
  std::vector<Point> points;
  std::vector<Extreme> extremes;
  std::vector<std::string> not_run;  // --collect: the cases with nothing written
  // Quick runs: every limit and extreme outcome, for reference-data/regression/stability_map_quick.csv.
  std::map<std::string, Observed> quick_record;
};

// The cases: "extremes" (the extreme cases) and one per point, named
// <coupling>_h<h>um_kl<scale>_kb<scale> (--list-cases; --only NAME computes one).
std::vector<std::string> cases(const Params& p);
Results run(const Params& p);
void write_tables(const Params& p, const Results& r);  // out_dir/check.md for the report

}  // namespace rbc::stability_map
