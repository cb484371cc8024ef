#pragma once
// Experiment constriction — 12 cells through a 15 um passage (Shi, Pan & Glowinski 2012,
// DOI 10.1002/fld.2455, Sec. 3.2, Figs. 11-13).
//
// Claim: in a 120 x 30 um channel with a 40 x 7.5 um block on each wall (centred at x1 = 60 um),
// driven by the body force of the straight channel at Re0 = 1.667, twelve s* = 0.481 cells
// (Hct 4.74 % of the fluid area) move toward the centre, squeeze through the passage and
// recover their biconcave shape after it; the mean velocity is 1.70 cm/s in the wide part and
// 3.33 cm/s in the narrow part (Re 0.4250 and 0.4163 with each part's own height).
//
// Method: the blocks are held at rest by the fictitious-domain multiplier of step 4
// (lib/fictitious_domain, paper/method/05_fictitious_domain.md); the cells by the semi-implicit
// coupling. Scene: experiments/constriction/constriction.toml (the cells' arrangement is ours).
// Definitions (the study's Sec. 3.2; reference-data/README.md): a part's mean velocity is the
// flux through each mesh section over its open height (30 or 15 um), averaged over the part's
// sections and over the samples (every 0.1 ms) of the window kWindow; Re = ρ U H/μ with the
// part's height.
//
// Run:  build/bin/constriction --check          (100 ms, about 10 min on 2 cores)
//       build/bin/constriction --quick --check  (2 ms on a 2x coarser mesh, seconds)
#include <map>
#include <string>
#include <vector>

#include "reference/reference_table.hpp"
#include "reference/regression_record.hpp"
#include "scene/run_scene.hpp"

namespace rbc::constriction {

// The averaging window of the mean velocities, s: the second half of the run (the flow develops
// in ≈ 1 ms, ρH²/μ = 0.75 ms; the cells spread along the channel in the first passages).
inline constexpr double kWindowStart = 0.05;
// Quick case: 2 ms at h = 0.625 um (window: its second half).
inline constexpr double kQuickEnd = 2e-3;

struct Params {
  std::string out_dir = "results/constriction";
  bool quick = false;
  int threads = 0;
  bool progress = true;
  bool resume = false;  // continue from the checkpoint in out_dir/run
  bool reuse = false;   // read a finished run in out_dir/run instead of running it again
  bool collect = false; // with reuse: run nothing; the rows of a run not finished (main or convergence) are "not run"
  // Error against run time (full runs only): short runs of the same scene over h and Δt with
  // both couplings, in out_dir/conv/<case>; compared at kConvTime with the finest explicit run.
  bool convergence = true;
  bool coarse_convergence = false;  // the convergence study on the coarse meshes alone (make reproduce)
  std::string only;  // run only this case (a name of cases()), no comparison
};

// The cases: the experiment's run (kMainRun, in out_dir/run) and, with the convergence study, its
// short runs (in out_dir/conv/<case>): --list-cases, --only NAME for GNU parallel or a Slurm array.
inline constexpr const char* kMainRun = "run";
std::vector<std::string> cases(const Params& p);

// The short horizon of the convergence study, s (the flow starts from rest; ρH²/μ = 0.75 ms).
inline constexpr double kConvTime = 1e-3;

struct ConvergenceRun {
  std::string coupling;
  double h = 0, dt = 0;            // m, s
  int substeps = 1;                // Q of the advection
  long steps = 0;
  double wall = 0;                 // s
  std::string failure;             // why the run stopped (empty: it reached kConvTime)
  std::vector<double> x, y;        // the cells' centroids at kConvTime, m
  double u_wide = 0;               // m/s at kConvTime
  double error = 0, u_error = 0;   // RMS centroid distance to the reference (m); |ΔU_wide|/U_wide
};

struct Results {
  RunSummary summary;
  bool collected_without_run = false;        // --collect found no finished main run: its rows are not run
  double window_start = 0, window_end = 0;   // s
  double u_wide = 0, u_narrow = 0;           // m/s, over the window
  double re_wide = 0, re_narrow = 0;
  double hematocrit = 0;                     // %, at t = 0
  double offset_start = 0, offset_entry = 0, offset_late = 0;  // mean |y − H/2| of the cells, m
  double entry_time = 0;                     // s: the leading cell reaches the passage
  int wide_cells_end = 0, biconcave_end = 0; // cells in the wide part at the end, and how many are biconcave (own frame)
  int biconcave_flow_frame_end = 0;          // and how many by the flow-frame descriptor
  std::vector<double> tilt_end;              // their long axes' angles to x1, degrees
  std::map<std::string, Measured> measured;  // ids of reference-data/constriction.csv
  std::map<std::string, Observed> quick_record;
  std::vector<ConvergenceRun> convergence;
};

Results run(const Params& params);

}  // namespace rbc::constriction
