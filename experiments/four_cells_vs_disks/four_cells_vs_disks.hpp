#pragma once
// Experiment four_cells_vs_disks — four cells of increasing bending stiffness against four rigid
// disks (Shi, Pan & Glowinski 2012, DOI 10.1002/fld.2455, Sec. 3.1.2, Figs. 6-8).
//
// Claim: in the wide channel (100 x 50 um, h = 0.3125 um, Re0 = 2.778) four s* = 1 cells released
// at (25, 10), (25, 40), (65, 10), (65, 40) um move toward the centreline and, after 200 ms, sit
// at a mean distance from it of 9.22, 9.38, 11.10, 12.23 um for k_b, 10 k_b, 100 k_b, 1000 k_b;
// four neutrally buoyant rigid disks of the cell's radius (2.8 um) at the same places stay at
// 12.73 um: the stiffest cells behave like the disks. Softer cells are visibly non-circular at the
// end, the 1000 k_b ones almost circular; four s* = 0.7 cells move much faster toward the
// centreline; cells and disks end staggered, not side by side. Re with the cells 2.710, 2.705,
// 2.685, 2.673 (s* = 0.7: 2.760).
//
// Method: the cells by the semi-implicit coupling (lib/semi_implicit), the disks by the
// distributed Lagrange multiplier of step 4 (lib/fictitious_domain/rigid_disks.hpp,
// paper/method/06_rigid_disks.md). Scene: four_cells_vs_disks.toml (channel, time, output) plus
// each case's bodies, added here.
//
// Definitions (the study's Sec. 3.1.2, and ours where the study is silent; reference-data/README.md):
//   distance  mean over the four bodies of |x2 − H/2| of the centroid, averaged over the samples
//             (every 0.1 ms) of the last millisecond;
//   Re        ρ U H / μ with U the mean velocity over the channel's section, same window;
//   circularity  (4πA/P²) / (π/(N tan(π/N))): the reduced area of the membrane polygon over that
//             of the regular N-gon, so that a circle of N nodes reads 1 (A, P from series.csv);
//             an ellipse of aspect ratio 1.1 reads 0.9955 and of 1.05 0.9988 (the thresholds of
//             the two shape claims, chosen before the first full run);
//   staggered  for each body, the x1-distance (periodic) to the nearest body on the other side of
//             the centreline, averaged; "staggered" when it is at least one cell diameter 2 R0 (judged
//             for the s* = 1 cells and the disks, Figs. 6-7).
//
// Cases (--list-cases; run one with --only NAME, collect with --check --reuse):
//   kb1 kb10 kb100 kb1000 s07 disks           the study's runs (k_b scales, s* = 0.7, disks)
//   kb1_seed1..3, disks_seed1..3              the ensemble: every body's centre moved by a
//                                             uniform amount in [-δ, δ]² (δ = kPerturbation) drawn
//                                             from a seeded Mersenne twister (reproducible)
//   kb1_dt3us, disks_dt3us, kb1_h0.625um, disks_h0.625um   Δt halved and h doubled (the error)
//   <case>_dt3us, <case>_dt1.5us, kb1000_dt0.75us   the Δt sequence of every study case (its
//                                             rows report 1.5 us, the 1000 k_b cells 0.75 us)
//   kb1_dt0.75us, kb1000_dt0.375us            one level below the reported run (evidence only)
//   one_disk_x2_10um.toml, one_disk_x2_20um.toml  (scenes for build/bin/rbcflow run) one disk from
//                                             either side of its equilibrium, to 400 ms
//   conv_*                                    error against run time on a 1.2 ms horizon (conv_sie_*:
//                                             the semi-implicit coupling in the extrapolated Lie
//                                             scheme, incremental form)
//   kb1_seed<s>_dt<l>us, kb1000_seed<s>_dt<l>us  paired seeds: the ensemble's starts (s = 1..5)
//                                             at each Δt level l = 3, 1.5, 0.75 us
//   kb1_explicit                              the study's explicit scheme, to kExplicitEnd
//   kb1_inc_dt<l>us                           the k_b cells in the incremental pressure form
//                                             (kIncrementalDts), beside the study's form
//   pg2002_h*_dt*, pg2002re12.78_h*_dt*       one disk against Pan & Glowinski (2002) at their
//                                             Re 96.74 and 12.78 (kDiskValidations): the
//                                             validation of our disks over Δt and h
//   disks_ring<s>h                            the four disks with their boundary's collocation
//                                             points s h apart (kRingSpacings: 2 and 4; the
//                                             method's is 1 h), at the disks' reported Δt: their
//                                             convergence in the disk's own resolution
//
// Run:  build/bin/four_cells_vs_disks --check            (every case, one after the other)
//       build/bin/four_cells_vs_disks --list-cases | parallel -j2 build/bin/four_cells_vs_disks --only {} --threads 1
//       build/bin/four_cells_vs_disks --check --reuse    (the table from the finished cases)
//       build/bin/four_cells_vs_disks --quick --check    (h = 0.625 um, 5 ms)
#include <array>
#include <map>
#include <string>
#include <vector>

#include "io/csv.hpp"
#include "reference/reference_table.hpp"
#include "reference/regression_record.hpp"
#include "scene/run_scene.hpp"

namespace rbc::four_cells_vs_disks {

// The study's places of the four bodies (m) and the disks' radius (the cell's R0), m.
inline const std::array<std::array<double, 2>, 4> kPlaces = {{{25e-6, 10e-6}, {25e-6, 40e-6}, {65e-6, 10e-6}, {65e-6, 40e-6}}};
inline constexpr double kDiskRadius = 2.8e-6;
// The ensemble's perturbation, m: below a mesh cell (0.3125 um), far below the bodies' size.
inline constexpr double kPerturbation = 0.25e-6;
// The rows' window: the last millisecond; the s* = 0.7 claim compares the approach to the
// centreline over the first kEarly seconds.
inline constexpr double kWindow = 1e-3;
inline constexpr double kEarly = 0.05;
// The shape claims' thresholds on the circularity (see above).
inline constexpr double kNonCircular = 0.9955;  // below: visibly non-circular (ellipse 1.1)
inline constexpr double kAlmostCircular = 0.9988;  // above: almost circular (ellipse 1.05)
// Quick case: h = 0.625 um, 5 ms.
inline constexpr double kQuickMesh = 0.625e-6, kQuickEnd = 5e-3;
// Our disk against published data (reference-data/disk_validation.csv): Pan & Glowinski's (2002)
// one-disk cases, one_disk_pan_glowinski_2002.toml at each of their Reynolds numbers, run over Δt
// at h = W/128 and over h (W/64, W/32) at the finest Δt. The disk's settled height over the width
// is averaged over the last kValidationWindow; the migration's rate is read as the height after s W
// travelled, at the digitized point of their trajectory nearest each nominal s.
inline constexpr double kValidationWindow = 1e-4;  // s (about 5 W travelled at Re0 106, 0.7 W at 13.9)
inline const std::string kValidationScene = "one_disk_pan_glowinski_2002.toml";
struct DiskValidation {
  std::string prefix;          // the cases' names: <prefix>_h<W/h>_dt<Δt in s>
  std::string label;           // their Reynolds number's label
  double reynolds0 = 0;        // Re0 = U W / nu of the cell-free channel; 0: the scene file's
  double end = 0;              // s; 0: the scene file's
  std::vector<double> dts;     // s, at h = W/128, finest first
  std::string equilibrium_id;  // the row of the settled height
  std::vector<std::pair<std::string, double>> travel;  // the rows read after s W travelled: id, s
  std::string trajectory;      // their digitized trajectory: reference-data/<trajectory>.csv
};
// Their label 96.74 (our Re0 106.09 from their nu and pressure gradient) and their lowest, 12.78
// (Re0 = 13.91 from the parameters tabulated with its trajectory in github.com/fradevita/FEN,
// test/small_test/fsi/Pan_Eulerian/postpro.py at commit 4e927b00: -dp/dx = 1.763e-3,
// nu = 3.2498036e-3 in units of W; their label is the Reynolds number of the flow with the disk,
// ours of the flow without it). The lower case takes about 7.6 times as long per W travelled, and
// about 1.7 times the distance to settle, so it runs to 8 ms (about 57 W travelled); its finest Δt, 4 times
// the other's, takes about twice as many steps per W / U0 (3000 against 1600).
inline const std::vector<DiskValidation> kDiskValidations = {
    {"pg2002", "96.74", 0, 0, {1.25e-8, 2.5e-8, 5e-8, 1e-7}, "pg2002_equilibrium", {{"pg2002_x2_s5", 5.0}, {"pg2002_x2_s10", 10.0}},
     "disk_validation_trajectory"},
    {"pg2002re12.78", "12.78", 13.91, 8e-3, {5e-8, 1e-7, 2e-7, 4e-7}, "pg2002re12.78_equilibrium",
     {{"pg2002re12.78_x2_s10", 10.0}, {"pg2002re12.78_x2_s20", 20.0}}, "disk_validation_trajectory_re12.78"}};
// The digitized point of a trajectory table (columns s_over_W, x2_over_W) nearest the distance
// travelled s / W: a migration-rate row's value is that point's x2 / W.
const CsvRecord& nearest_digitized_point(const std::vector<CsvRecord>& points, double s_over_W);
// Error against run time: from rest to kConvTime (a whole number of every Δt of the study:
// 1.2 ms = 100 x 12 us = 48000 x 25 ns, so that all runs compare at the same instant).
inline constexpr double kConvTime = 1.2e-3;
// The paired-seed ensembles of the k_b and 1000 k_b cells (kb1_seed<s>_dt<level>us,
// kb1000_seed<s>_dt<level>us): the Δt levels, s, finest first.
inline const std::vector<double> kPairedDts = {0.75e-6, 1.5e-6, 3e-6};
// The study's explicit scheme for the k_b cells (kb1_explicit): Δt, s, at three quarters of the
// one-cell stability limit at this h (8e-8 s: stability_map), and its end, s: the study's 200 ms
// (3.3 million steps, about 70 min on one core; its first 50 ms are the trajectory compared).
inline constexpr double kExplicitDt = 6e-8, kExplicitEnd = 0.2;
// The k_b cells by the semi-implicit coupling in the incremental form of the pressure
// (kb1_inc_dt<l>us, the study's places, to 200 ms): the Δt levels, s, coarsest first. Beside the
// study's form and the explicit run: which form's Δt error is the smaller on these cells.
inline const std::vector<double> kIncrementalDts = {6e-6, 3e-6, 1.5e-6};
// The four disks' boundary points over their spacing (disks_ring<s>h, in h; the method's 1 h is
// the reported run itself), at the disks' reported Δt: coarser only, since below about h apart
// the points over-determine the multiplier (rigid_disks.hpp).
inline const std::vector<double> kRingSpacings = {2.0, 4.0};

struct Case {
  std::string name;
  std::string role;            // "study", "ensemble", "evidence", "convergence"
  bool disks = false;          // four disks, or four cells
  double swelling_ratio = 1.0, kb_scale = 1.0;
  unsigned seed = 0;           // 0: the study's places
  double h = 0, dt = 0, end = 0;  // m, s, s; 0: the scene file's
  std::string coupling;        // empty: the scene file's
  std::string projection;      // the pressure's form ("study", "incremental"); empty: the scene file's
  std::string scheme;          // the time scheme ("lie", "lie-extrapolated"); empty: the scene file's
  std::string scene_file;      // empty: four_cells_vs_disks.toml plus the bodies; else this file as it is
  double reynolds0 = 0;        // Re0 of the cell-free channel (scene_file cases); 0: the file's
  double ring_spacing = 0;     // the disks' boundary points, h apart ([solver] disk_boundary_spacing); 0: the scene's
  bool reported = false;       // the run the study's rows and figures read: the case's finest Δt
};

struct Params {
  std::string out_dir = "results/four_cells_vs_disks";
  bool quick = false;
  int threads = 0;
  bool progress = true;
  bool resume = false;   // a case whose folder holds a checkpoint continues from it
  bool reuse = false;    // a case whose folder holds a finished run of the same scene is read
  bool collect = false;  // read back the finished cases only; run none (the others "not run")
  std::string only;      // run this case only (exact name), no comparison
  std::vector<unsigned> seeds = {1, 2, 3};
  std::vector<unsigned> paired_seeds = {1, 2, 3, 4, 5};  // with seed 0 (the study's places): six
  bool evidence = true;     // the Δt-halved and h-doubled full runs
  bool convergence = true;  // the 1.2 ms error-against-run-time study
  // The reported runs only, none of the evidence (make reproduce: u_num as recorded by make
  // evidence, reference/recorded_uncertainty.hpp). The quick parameters ignore it.
  bool study_only = false;
};

// The cases of a run with these parameters, the longest first (GNU parallel starts them in
// this order).
std::vector<Case> cases(const Params& p);
// The case's scene (the file plus its bodies and overrides).
Scene case_scene(const Case& c, bool quick);

struct CaseResult {
  Case spec;
  double h = 0, dt = 0, length = 0;     // the scene's mesh size, time step, channel length (m, s, m)
  RunSummary summary;
  std::string failure;               // why the run stopped (empty: it reached its end)
  std::vector<double> t;             // s, the samples
  std::vector<std::array<double, 4>> x, y;  // the bodies' centroids, m
  std::array<double, 4> circularity_end{};  // cells only
  double distance = 0, reynolds = 0;        // over the last kWindow (validation: the disk's x2 / W over kValidationWindow)
  double distance_early = 0;                // at kEarly (or the end if shorter)
  double stagger = 0;                       // m, at the end
  long contact_steps = 0;                   // disks: steps in which the contact force acted
};

struct Results {
  std::map<std::string, CaseResult> cases;
  std::map<std::string, Measured> measured;       // ids of reference-data/four_cells_vs_disks.csv
  std::map<std::string, Measured> validation;     // ids of reference-data/disk_validation.csv
  std::map<std::string, Observed> quick_record;
  std::string spread_md, convergence_md;          // the u_num evidence and the work-precision table
  std::string validation_md;                      // the disk against published data
};

Results run(const Params& p);

// A distance (bool re false, um) or Re row of a study case (base: "kb1", ..., "disks") with its
// u_num's parts from the cases in res: the Δt part and the start spread (pooled) from the paired starts
// where they finished at every level of kPairedDts, else from the case's Δt levels and the 6 us
// start ensemble; the window noise of the reported run (its series.csv under p.out_dir).
Measured row_with_uncertainty(const Params& p, const Results& res, const std::string& base, bool re, const std::string& note);

}  // namespace rbc::four_cells_vs_disks
