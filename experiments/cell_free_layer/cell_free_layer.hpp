#pragma once
// Experiment cell_free_layer — many cells and the plasma layer next to the walls (Shi, Pan &
// Glowinski 2012, DOI 10.1002/fld.2455, Sec. 3.1.3, Figs. 9-10).
//
// Claim: in the wide channel (100 x 50 um, h = 0.3125 um, Re0 = 2.778) 50 s* = 0.7 cells
// (Hct 17.24 %, to 150 ms) and 100 cells (Hct 34.48 %, to 200 ms) leave a cell-free layer next to
// each wall of 6.24 um and 2.94 um (mean of the two walls, last millisecond), close to the
// empirical estimate 100/Hct um (5.8 and 2.9 um); Re with the cells 2.346 and 1.677.
//
// Method: the cells by the semi-implicit coupling (lib/semi_implicit), the pressure in its
// incremental form (cell_free_layer.toml, README.md: Deviations); the health check
// stops a run whose membranes cross (lib/membrane/membrane_crossing.hpp). Scene:
// cell_free_layer.toml (channel, time, output) plus each case's cells, added here.
//
// The initial arrangement (the study shows it only in its figures; ours, stated and seeded):
// the cells lie on a lattice of 10 columns and n/10 rows, row r at x2 = (r + 1/2) H / rows,
// column c at x1 = (c + 1/2) L / 10, odd rows shifted by half a column; every cell's long axis
// along x1 (our choice wherever the study does not state it). Each centre is then moved by a
// uniform amount in [−δ1, δ1] x [−δ2, δ2] drawn from the case's seed (a Mersenne twister's raw
// output, the same on every platform): δ1 = 1 um, and δ2 all the room the rows leave, half of
// H/rows less a cell's thickness (3.4 um) and 0.8 um kept between rows: 0.4 um for the 100 cells
// (rows 5 um apart), 2.9 um for the 50 (10 um apart), so that the 50 cells' starts differ as much as
// their rows allow. Seed 1 is the study's case; seeds 2 to 6 the ensemble (six arrangements).
//
// Definitions (the study's Sec. 3.1.3; reference-data/README.md):
//   cell-free layer  at each sample the gap between a wall and the membrane node (of any cell)
//                    closest to it (series.csv wall_gap_lower, wall_gap_upper), averaged over the
//                    samples (every 0.1 ms) of the last millisecond; each wall and their mean
//                    (beside it, not a row: the mean of the walls over the run's second half,
//                    which the layer's fluctuations of about 0.2 um disturb less);
//   Hct              Σ cell areas / (L H), the same window; the empirical estimate is 100/Hct um;
//   Re               ρ U H / μ with U the mean velocity over the section, the same window;
//   Hct profile      the area fraction of cells at height x2, Σ_cells chord(x2) / L (chord: the
//                    length of the line x2 = const inside the membrane polygon), on bins of h,
//                    averaged over the snapshots of the last kProfileWindow.
//
// Cases (--list-cases; run one with --only NAME, collect with --check --reuse):
//   n50 n100                         the study's runs (seed 1)
//   n50_seed2..6, n100_seed2..6      the ensemble (other arrangements), Δt = 3 us
//   n50_dt1.5us_seed2..6, n100_dt1.5us_seed2..6  the same arrangements at the rows' Δt
//   n100_early_study_dt<l>us, n100_early_inc_dt<l>us  100 cells to kEarlyEnd in the study's and
//                                    the incremental form of the pressure, Δt = 3, 1.5, 0.75,
//                                    0.375 us: does the study's form converge to the other's answer?
//   n50_dt1.5us, n50_h0.625um, ...   Δt halved and h doubled (the error)
//   n100_wide_gaps                   100 cells started about 2.9 um off the walls (kWideGapMargin)
//   n100_explicit_early              100 cells, the study's own scheme (explicit coupling, the study's
//                                    form of the pressure), to 20 ms (kEarlyEnd)
//   n50_repulsion                    the 50 cells with the 100-cell cases' membrane repulsion
//   n50_study_pressure, n100_study_pressure  the study's cases with the study's form of the
//                                    pressure splitting (the cause of the deviation the experiment
//                                    had in that form: README.md, Deviations); n100_study_pressure_dt1.5us
//                                    its Δt/2
//   n100_no_repulsion                100 cells without the repulsion (the study's model), to 200 ms:
//                                    does the incremental form's crowd still need it? (README.md)
//   conv_*                           error against run time on a 1.2 ms horizon (50 cells;
//                                    conv_*_inc_*: the incremental form, the others the study's)
//
// Run:  build/bin/cell_free_layer --list-cases | parallel -j2 build/bin/cell_free_layer --only {} --threads 1
//       build/bin/cell_free_layer --check --reuse    (the table from the finished cases)
//       build/bin/cell_free_layer --quick --check    (h = 0.625 um, 3 ms)
#include <map>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "reference/reference_table.hpp"
#include "reference/regression_record.hpp"
#include "scene/run_scene.hpp"

namespace rbc::cell_free_layer {

// The arrangement: 10 columns; the perturbation's half-widths, m.
inline constexpr int kColumns = 10;
inline constexpr double kShiftX = 1e-6;
inline constexpr double kCellThickness = 3.4e-6, kRowClearance = 0.8e-6;
// δ2 of a lattice of `rows` rows over the height H, m (above).
inline double shift_y(int rows, double H) { return 0.5 * (H / rows - kCellThickness - kRowClearance); }
inline constexpr double kSwellingRatio = 0.7;
// The rows' window: the last millisecond; the Hct profile's: the last 20 ms (snapshots every 1 ms).
inline constexpr double kWindow = 1e-3;
inline constexpr double kProfileWindow = 20e-3, kProfileEvery = 1e-3;
// Quick case: h = 0.625 um, 3 ms.
inline constexpr double kQuickMesh = 0.625e-6, kQuickEnd = 3e-3;
// The membrane repulsion of the 100-cell cases (lib/membrane/membrane_repulsion.hpp): strength,
// N/m, and range in mesh cells. Without it the 100 cells reach a wall at 10.1 ms (Δt = 3e-6 s;
// at 6e-6 s, 4.0 ms); with it they kept 0.50-0.70 um off the walls to 34.7 ms (measured
//, README.md; the study's form of the pressure, the scheme then). In the incremental
// form (now the scene file's) the 100 cells keep apart without it for the full 200 ms
// (n100_no_repulsion, rows within the arrangements' spread of the run with it); it stays on in
// the 100-cell cases because it makes their steps about 2.5 times cheaper (fewer GMRES iterations
// and block rebuilds). The 50 cells run without it (the study's model); n50_repulsion measures its
// effect on their rows.
inline constexpr double kRepulsionStrength = 1e-3, kRepulsionRangeCells = 2.0;
// Error against run time: the study's 50 cells from rest to kConvTime (a whole
// number of every Δt of the study), both couplings, h = 0.3125 and 0.625 um, Δt halved in turn;
// the error of the 50 centroids against the explicit run at h = 0.3125 um and the smallest Δt.
inline constexpr double kConvTime = 1.2e-3;
// The 100 cells from wider wall gaps (n100_wide_gaps): the lattice's rows kept kWideGapMargin in
// from each wall, which moves the lowest and highest rows 0.9 kWideGapMargin further from the
// walls: the seed-1 gaps of 0.89 and 0.84 um at t = 0 become about 2.9 um, the study's 100-cell
// layer. Does the layer the crowd reaches depend on where it starts? (README.md)
inline constexpr double kWideGapMargin = 2.25e-6;
// The 100 cells' early layer with the study's own (explicit) coupling (n100_explicit_early): Δt =
// kExplicitDt, below its stability limit (6e-8 s for 100 cells at this h: bench_channel), to
// kEarlyEnd; compared with the semi-implicit runs at 3 and 1.5 us (both forms of the pressure) over the window
// [kEarlyFrom, kEarlyEnd], where they already part, and over the second half of kConvTime
// (early_layer_table; there also the 50 cells' 1.2 ms runs of both couplings).
inline constexpr double kExplicitDt = 5e-8, kEarlyFrom = 2e-3, kEarlyEnd = 20e-3;
// The pressure forms' Δt ladder to kEarlyEnd (n100_early_*), s, finest first.
inline const std::vector<double> kFormDts = {0.1875e-6, 0.375e-6, 0.75e-6, 1.5e-6, 3e-6};

struct Case {
  std::string name;
  std::string role;     // "study", "ensemble", "evidence", "convergence"
  int cells = 50;       // 50 or 100
  unsigned seed = 1;    // the arrangement's perturbation (0: the lattice itself)
  double h = 0, dt = 0, end = 0;  // m, s, s; 0: the scene file's (end: 150 ms for 50 cells, 200 ms for 100)
  double repulsion = 0;           // N/m, range kRepulsionRangeCells h; 0: off
  std::string coupling;           // "explicit" or "semi-implicit"; empty: the scene file's
  double margin = 0;              // m: the lattice's rows kept this far in from each wall (arrangement())
  std::string projection;         // "study" or "incremental" (ChannelFlowParams); empty: the scene file's
  std::string scheme;             // "lie" or "lie-extrapolated" ([time] scheme); empty: the scene file's
  bool reported = false;          // the run the study's rows and figures read (the finest Δt)
  bool read_only = false;         // read back where finished or kept (paper/keep_evidence.sh),
                                  // never run: the rows' ensemble under --study-only
};

struct Params {
  std::string out_dir = "results/cell_free_layer";
  bool quick = false;
  int threads = 0;
  bool progress = true;
  bool resume = false;
  bool reuse = false;
  bool collect = false;  // read back the finished cases only; run none (the others "not run")
  std::string only;
  std::vector<unsigned> seeds = {2, 3, 4, 5, 6};  // the ensemble besides the study's seed 1 (six members: README.md)
  bool evidence = true;
  bool convergence = true;  // the 1.2 ms error-against-run-time runs
  // The reported runs only, none of the evidence (make reproduce: u_num as recorded by make
  // evidence, reference/recorded_uncertainty.hpp). The quick parameters ignore it.
  bool study_only = false;
};

// The cells' centres of an arrangement of n cells (m), in the channel L x H, the lattice's rows
// spread evenly over margin < x2 < H − margin (0: the whole height).
std::vector<Eigen::Vector2d> arrangement(int n, unsigned seed, double L, double H, double margin = 0);
std::vector<Case> cases(const Params& p);
Scene case_scene(const Case& c, bool quick);

struct CaseResult {
  Case spec;
  std::string code;  // the code that made a kept run (empty: this code)
  double h = 0, dt = 0, length = 0;  // m, s, m (the channel's, periodic)
  RunSummary summary;
  std::string failure;
  std::vector<double> t, gap_lower, gap_upper, hematocrit, reynolds;  // the samples (s, m, m, %, -)
  double layer_lower = 0, layer_upper = 0, layer = 0;  // m, over the last kWindow
  double layer_late = 0;                                // m, mean of the walls over the run's second half (less noisy; not a row)
  double hct = 0, re = 0;                               // %, -, same window
  long repulsion_steps = 0;                             // steps in which the membrane repulsion acted (summary.json)
  std::vector<Eigen::Vector2d> centroids_end;           // m, every cell's centroid at the last sample
  std::vector<double> profile_y, profile;               // m, area fraction (0..1), over the last kProfileWindow
};

struct Results {
  std::map<std::string, CaseResult> cases;
  std::map<std::string, Measured> measured;
  std::map<std::string, Observed> quick_record;
  std::string ensemble_md;     // every row's mean and spread over the arrangements, and the Δt/h changes
  std::string convergence_md;  // the work-precision table
};

Results run(const Params& p);

// The ensemble table (Markdown): every row over the arrangements, mean, sample standard deviation,
// the Δt/2, 2h and repulsion runs' changes and the tolerance by the README's rule. Public for the
// test of the rule.
std::string ensemble_table(const Params& p, const Results& res);
// The early layer (Markdown), the mean of the walls over the second half of kConvTime (50 and 100
// cells) and over [kEarlyFrom, kEarlyEnd] (100 cells), for the explicit coupling and the
// semi-implicit one at each Δt; empty if none of those runs is in. Public for its test.
std::string early_layer_table(const Results& res);
// The study's form of the pressure against the incremental one (Markdown): the 100 cells' layer
// and Re over [kEarlyFrom, kEarlyEnd] at each of kFormDts, the study's scheme (n100_explicit_early)
// beside them, and each form's Δt -> 0 limit over its consecutive finished levels (at least three).
std::string form_table(const Results& res);
// The pressure forms' ladder: a case's name at Δt dt, s (projection "study" or "incremental").
std::string form_case_name(const std::string& projection, double dt);

// The time-averaged area fraction of the membranes in snapshots.dat over t ≥ from, on bins of
// width dy across 0 < x2 < H (bin centres in y, fractions 0..1); channel length L. Public for the
// test (a known arrangement's profile integrates to its hematocrit).
void hematocrit_profile(const std::string& snapshots, double from, double L, double H, double dy, std::vector<double>& y,
                        std::vector<double>& fraction);

}  // namespace rbc::cell_free_layer
