// The cell_free_layer experiment: its stated initial arrangement, the hematocrit profile it
// draws, its quick case (3 ms, h = 0.625 um) against the committed regression record, and
// collecting finished cases without running the others (--collect).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>

#include "cell_free_layer/cell_free_layer.hpp"
#include "common/case_runner.hpp"

namespace rbc {
namespace {

namespace fs = std::filesystem;
using namespace cell_free_layer;

TEST(CellFreeLayerExperiment, ArrangementIsTheStatedSeededLatticeAndTheScenesAcceptIt) {
  const double L = 100e-6, H = 50e-6;
  for (int n : {50, 100}) {
    const auto lattice = arrangement(n, 0, L, H);
    ASSERT_EQ(int(lattice.size()), n);
    const int rows = n / kColumns;
    // Row r at (r + 1/2) H / rows; odd rows shifted by half a column.
    EXPECT_DOUBLE_EQ(lattice[0].x(), 0.5 * L / kColumns);
    EXPECT_DOUBLE_EQ(lattice[0].y(), 0.5 * H / rows);
    EXPECT_DOUBLE_EQ(lattice[kColumns].x(), 1.0 * L / kColumns);
    EXPECT_DOUBLE_EQ(lattice[n - 1].y(), (rows - 0.5) * H / rows);
    // A seed moves every centre within the stated half-widths, and the same seed gives the same start.
    for (unsigned seed : {1u, 2u, 3u}) {
      const auto moved = arrangement(n, seed, L, H);
      EXPECT_EQ(moved, arrangement(n, seed, L, H));
      int changed = 0;
      for (int k = 0; k < n; ++k) {
        EXPECT_LE(std::abs(moved[k].x() - lattice[k].x()), kShiftX);
        EXPECT_LE(std::abs(moved[k].y() - lattice[k].y()), shift_y(rows, H));
        changed += moved[k] != lattice[k];
      }
      EXPECT_EQ(changed, n);
    }
  }
  // δ2: all the room between the rows (0.8 um kept): 0.4 um for the 100 cells, 2.9 um for the 50.
  EXPECT_NEAR(shift_y(10, H), 0.4e-6, 1e-15);
  EXPECT_NEAR(shift_y(5, H), 2.9e-6, 1e-15);
  EXPECT_THROW(arrangement(55, 1, L, H), std::invalid_argument);
  // A margin spreads the same rows over margin < x2 < H − margin (n100_wide_gaps): the lowest and
  // highest rows 0.9 margin further in, the columns and the seed's shifts unchanged.
  {
    const auto plain = arrangement(100, 1, L, H), wide = arrangement(100, 1, L, H, kWideGapMargin);
    EXPECT_EQ(plain, arrangement(100, 1, L, H, 0.0));
    for (int k = 0; k < 100; ++k) {
      const int r = k / kColumns;
      EXPECT_DOUBLE_EQ(wide[k].x(), plain[k].x());
      EXPECT_NEAR(wide[k].y() - plain[k].y(), kWideGapMargin * (1 - (2 * r + 1) / 10.0), 1e-15);
    }
  }
  // Every case's scene parses: the cells inside the channel and apart (scene validation), the
  // study's hematocrit from the cells' target areas (s* π R0² each).
  Params p;
  for (const Case& c : cases(p)) {
    const Scene s = case_scene(c, false);
    ASSERT_EQ(int(s.cells.size()), c.cells) << c.name;
    const double hct = 100.0 * c.cells * kSwellingRatio * std::numbers::pi * 2.8e-6 * 2.8e-6 / (s.length * s.height);
    EXPECT_NEAR(hct, c.cells == 50 ? 17.24 : 34.48, 0.005) << c.name;
    if (c.role == "convergence") {  // from rest to the common horizon, the coupling and Δt named
      EXPECT_NEAR(s.end, kConvTime - 0.5 * c.dt, 1e-15) << c.name;
      EXPECT_EQ(s.coupling, c.coupling) << c.name;
      EXPECT_EQ(s.dt, c.dt) << c.name;
      EXPECT_NEAR(std::round(kConvTime / s.dt) * s.dt, kConvTime, 1e-9 * s.dt) << c.name;  // a whole number of steps
    } else if (c.name == "n100_explicit_early") {  // the study's coupling below its limit, to kEarlyEnd
      EXPECT_EQ(s.end, kEarlyEnd);
      EXPECT_EQ(s.coupling, "explicit");
      EXPECT_EQ(s.dt, kExplicitDt);
    } else if (c.role == "form") {  // the pressure forms' Δt ladder, to kEarlyEnd
      EXPECT_EQ(s.end, kEarlyEnd) << c.name;
      EXPECT_EQ(s.dt, c.dt) << c.name;
      EXPECT_EQ(c.cells, 100) << c.name;
    } else {
      EXPECT_EQ(s.end, c.cells == 50 ? 0.15 : 0.2) << c.name;
    }
    // The study's form of the pressure in its evidence runs (*_study_pressure*), the study's own
    // scheme (n100_explicit_early) and the 1.2 ms runs not named _inc; the incremental form (the
    // scene file's) everywhere else.
    const bool study_form = c.name.find("_study_pressure") != std::string::npos || c.name == "n100_explicit_early" ||
                            c.name.find("_early_study_") != std::string::npos ||
                            (c.role == "convergence" && c.name.find("_inc_") == std::string::npos);
    EXPECT_EQ(s.projection, study_form ? "study" : "incremental") << c.name;
    EXPECT_EQ(s.scheme, c.name.rfind("conv_sie_", 0) == 0 ? "lie-extrapolated" : "lie") << c.name;  // the work-precision's third scheme
    // The membrane repulsion: on (range 2h) in the 100-cell cases but one and in n50_repulsion.
    const bool repelled = (c.cells == 100 && c.name != "n100_no_repulsion") || c.name == "n50_repulsion";
    EXPECT_EQ(s.repulsion_strength, repelled ? kRepulsionStrength : 0.0) << c.name;
    if (repelled) {
      EXPECT_DOUBLE_EQ(s.repulsion_range, kRepulsionRangeCells * s.mesh_size) << c.name;
    }
  }
  // The quick 100-cell case too (at its own h).
  Case q;
  q.cells = 100;
  q.repulsion = kRepulsionStrength;
  const Scene s = case_scene(q, true);
  EXPECT_DOUBLE_EQ(s.mesh_size, kQuickMesh);
  EXPECT_DOUBLE_EQ(s.repulsion_range, kRepulsionRangeCells * kQuickMesh);
}

// make reproduce runs --study-only: the runs the rows report (Δt halved), none of the evidence.
TEST(CellFreeLayerExperiment, StudyOnlyIsTheTwoReportedRunsAndTheCoarseConvergenceRuns) {
  Params p;
  p.study_only = true;
  std::vector<std::string> names;
  int read_only = 0, coarse_convergence = 0;
  for (const Case& c : cases(p)) {
    if (c.role == "convergence") {  // the error against run time on the coarse mesh (case_runner.hpp)
      EXPECT_GE(c.h, case_runner::kReportConvergenceMinH) << c.name;
      EXPECT_FALSE(c.read_only) << c.name;
      ++coarse_convergence;
      continue;
    }
    if (!c.read_only) names.push_back(c.name);
    // The rows' other arrangements at their Δt and all of them at 3 us (the Δt pairs): read back
    // where finished or kept, never run.
    if (c.read_only) {
      EXPECT_TRUE(c.role == "ensemble_reported" || c.role == "ensemble" || c.role == "study") << c.name;
      EXPECT_TRUE(c.dt == 1.5e-6 || c.dt == 0) << c.name;  // (0: the scene's 3 us)
      ++read_only;
    }
  }
  EXPECT_EQ(names, (std::vector<std::string>{"n100_dt1.5us", "n50_dt1.5us"}));
  EXPECT_EQ(coarse_convergence, 9);  // explicit 2, semi-implicit (incremental p) 4 and extrapolated 3, at h = 0.625 um
  EXPECT_EQ(read_only, 2 * (2 * int(p.seeds.size()) + 1));
  EXPECT_GE(p.seeds.size() + 1, kEnsembleMinimum);  // seed 1 and the others: a decidable ensemble
  Params quick;
  quick.quick = true;
  quick.study_only = true;
  EXPECT_EQ(cases(quick).size(), 2u);
}

TEST(CellFreeLayerExperiment, HematocritProfileOfKnownCirclesIsTheirChords) {
  // Two circles of radius R at heights 10 and 30 um in a 100 x 50 um channel, in two snapshots
  // (one before the window, which must not count).
  const double L = 100e-6, H = 50e-6, R = 2.8e-6;
  const fs::path f = fs::temp_directory_path() / "rbcflow_cfl_profile.dat";
  {
    std::ofstream o(f);
    for (double t : {0.0, 0.01}) {
      o << "# t = " << t << " s\n";
      for (double yc : {10e-6, 30e-6}) {
        o << "# cell\n";
        const int N = 400;
        for (int i = 0; i <= N; ++i) {
          const double a = 2 * std::numbers::pi * i / N;
          o << 20e-6 + (t > 0 ? R : 2 * R) * std::cos(a) << " " << yc + (t > 0 ? R : 2 * R) * std::sin(a) << "\n";
        }
        o << "\n";
      }
      o << "\n";
    }
  }
  std::vector<double> y, phi;
  hematocrit_profile(f.string(), 0.005, L, H, 0.25e-6, y, phi);
  ASSERT_EQ(y.size(), 200u);
  double integral = 0;
  for (std::size_t b = 0; b < y.size(); ++b) {
    integral += phi[b] * 0.25e-6;
    const double d = std::min(std::abs(y[b] - 10e-6), std::abs(y[b] - 30e-6));
    const double chord = d < R ? 2 * std::sqrt(R * R - d * d) : 0.0;
    EXPECT_NEAR(phi[b], chord / L, 2e-3) << "x2 = " << y[b];  // the polygon's chords within 0.2 um
  }
  // ∫ φ dx2 = Σ areas / L (the hematocrit times H).
  EXPECT_NEAR(integral, 2 * std::numbers::pi * R * R / L, 0.01 * 2 * std::numbers::pi * R * R / L);
  EXPECT_THROW(hematocrit_profile(f.string(), 1.0, L, H, 0.25e-6, y, phi), std::runtime_error);
  fs::remove(f);
}

// The ensemble table shows every row over the arrangements with its spread and the evidence runs'
// changes (u_num's parts); no tolerance of ours (they come from the study alone).
TEST(CellFreeLayerExperiment, EnsembleTableShowsTheSpreadAndTheEvidenceRunsChanges) {
  Params p;
  p.seeds = {2, 3, 4};  // seed 4 not run: said in its place, left out of the mean and s
  Results res;
  auto put = [&](const std::string& name, double layer_um, double re) {
    CaseResult r;
    r.layer = r.layer_lower = r.layer_upper = layer_um * 1e-6;
    r.re = re;
    r.hct = 17.24;
    res.cases[name] = r;
  };
  put("n50", 5.0, 2.30);
  put("n50_seed2", 5.4, 2.32);
  put("n50_seed3", 4.6, 2.28);
  put("n50_dt1.5us", 5.3, 2.31);
  put("n50_h0.625um", 4.1, 2.10);
  put("n50_study_pressure", 5.8, 2.30);
  // s of {5.0, 5.4, 4.6} = 0.4; the changes against seed 1; the missing runs as "-".
  const std::string md = ensemble_table(p, res);
  EXPECT_NE(md.find("| 50 cells: cell-free layer, mean of the walls (um) | 5 | 5.4 4.6 (seed 4: not run) | 5 | 0.4 | +0.3 | +0.8 | - | -0.9 | - |\n"), std::string::npos) << md;
  EXPECT_NE(md.find("| 50 cells: Hct (%) |"), std::string::npos);
  EXPECT_EQ(md.find("tolerance by the rule"), std::string::npos);
}

// The early-layer table averages the two walls' gaps over its windows, leaves out runs that
// stopped or ended before a window's end, and is empty without any of its runs.
// A run sampled every 0.1 ms from 0 to `end` (s) whose mean of the two walls' gaps is gap_um
// (um) throughout, at Reynolds number re.
CaseResult steady_run(double end, double gap_um, double re = 0) {
  CaseResult r;
  for (double t = 0; t <= end + 1e-12; t += 1e-4) {
    r.t.push_back(t);
    r.gap_lower.push_back((gap_um - 0.5) * 1e-6);
    r.gap_upper.push_back((gap_um + 0.5) * 1e-6);
    r.reynolds.push_back(re);
  }
  r.re = re;
  return r;
}

TEST(CellFreeLayerExperiment, EarlyLayerTableAveragesTheWallsOverItsWindows) {
  Results res;
  EXPECT_EQ(early_layer_table(res), "");
  auto put = [&](const std::string& name, double end, double gap_um) { res.cases[name] = steady_run(end, gap_um); };
  put("n100_explicit_early", kEarlyEnd, 2.0);
  put("n100", 0.2, 0.5);
  put("n100_dt1.5us", 1.5e-3, 1.0);  // ended before the second window: "-" there
  put("conv_si_h0.3125_dt3e-06", kConvTime, 2.5);
  put("n100_study_pressure", 0.2, 0.75);
  res.cases["n100_study_pressure_dt1.5us"] = res.cases["n100"];
  res.cases["n100_study_pressure_dt1.5us"].failure = "stopped";  // left out
  const std::string md = early_layer_table(res);
  EXPECT_NE(md.find("| 100 | explicit, study's p (the study's scheme) | 0.05 | 2.000 | 2.000 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 100 | semi-implicit, incremental p (the study's case) | 3 | 0.500 | 0.500 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 100 | semi-implicit, incremental p | 1.5 | 1.000 | - |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 50 | semi-implicit, study's p | 3 | 2.500 | - |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 100 | semi-implicit, study's p | 3 | 0.750 | 0.750 |"), std::string::npos) << md;
  EXPECT_EQ(md.find("| 100 | semi-implicit, study's p | 1.5 |"), std::string::npos) << md;
}

// The pressure forms' table: each form's limit from its levels (exactly first order here) and its
// distance from the study's scheme; a level that both forms miss ends each form's sequence, so no
// limit is drawn from levels that are not halvings of one another.
TEST(CellFreeLayerExperiment, FormTableFitsEachFormsConsecutiveLevelsAgainstTheStudysScheme) {
  Results res;
  EXPECT_EQ(form_table(res), "");
  auto put = [&](const std::string& name, double layer_um, double re) { res.cases[name] = steady_run(kEarlyEnd, layer_um, re); };
  for (double dt : {0.375e-6, 0.75e-6, 1.5e-6, 3e-6}) {
    const double us = dt * 1e6;
    put(form_case_name("study", dt), 1.5 - 0.2 * us, 1.34 - 0.02 * us);
    put(form_case_name("incremental", dt), 1.6 + 0.01 * us, 1.35 + 0.001 * us);
  }
  put("n100_explicit_early", 1.5, 1.34);
  std::string md = form_table(res);
  EXPECT_NE(md.find("| 3 | 0.900 | 1.630 | -0.730 | 1.2800 | 1.3530 | -0.0730 | -0.0730 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| explicit, 0.05 (the study's scheme) | 1.500 | | | 1.3400 |"), std::string::npos) << md;
  EXPECT_NE(md.find("layer (um) as dt -> 0: the study's form 1.5 ("), std::string::npos) << md;
  EXPECT_NE(md.find("the incremental form 1.6 ("), std::string::npos) << md;
  EXPECT_NE(md.find("Re as dt -> 0: the study's form 1.34 ("), std::string::npos) << md;
  EXPECT_NE(md.find("The study's scheme (n100_explicit_early) 1.5: "), std::string::npos) << md;
  // Both forms miss 0.75 us: 0.375 us alone is consecutive from the finest, too few for a limit.
  res.cases.erase(form_case_name("study", 0.75e-6));
  res.cases.erase(form_case_name("incremental", 0.75e-6));
  md = form_table(res);
  EXPECT_NE(md.find("| 3 | 0.900 |"), std::string::npos) << md;
  EXPECT_EQ(md.find("as dt -> 0"), std::string::npos) << md;
}

// The work-precision table's CSV is split at commas by plot.gp (awk -F,): a kind with a comma is
// refused, and the kinds this experiment writes have eight fields a line.
TEST(CellFreeLayerExperiment, ConvergenceCsvKeepsItsColumns) {
  const fs::path csv = fs::temp_directory_path() / "rbcflow_cfl_convergence.csv";
  case_runner::ConvergenceRow row;
  row.kind = "semi-implicit, incremental p";
  row.h = 0.3125e-6;
  row.dt = 3e-6;
  row.steps = 400;
  row.wall_seconds = 9.6;
  EXPECT_THROW(case_runner::convergence_table({row}, csv.string(), ""), std::invalid_argument);
  row.kind = "semi-implicit + incremental p";
  case_runner::convergence_table({row, row}, csv.string(), "");
  std::ifstream f(csv);
  std::string line;
  int lines = 0;
  while (std::getline(f, line)) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 7) << line;
    ++lines;
  }
  EXPECT_EQ(lines, 3);
}

TEST(CellFreeLayerExperiment, QuickRunMatchesItsRegressionRecord) {
  Params p;
  p.quick = true;
  p.progress = false;
  p.threads = 1;
  p.out_dir = (fs::temp_directory_path() / "rbcflow_cell_free_layer_quick").string();
  fs::remove_all(p.out_dir);
  const auto r = run(p);
  ASSERT_EQ(r.cases.size(), 2u);
  for (const auto& [name, c] : r.cases) {
    EXPECT_TRUE(c.failure.empty()) << name << ": " << c.failure;
    EXPECT_NEAR(c.hct, c.spec.cells == 50 ? 17.24 : 34.48, 0.05) << name;  // areas kept within 0.3 %
    EXPECT_GT(c.layer_lower, 0.0) << name;
    EXPECT_GT(c.layer_upper, 0.0) << name;
    // The profile integrates to the hematocrit (within the chords' and the bins' error).
    double integral = 0;
    for (double v : c.profile) integral += v;
    EXPECT_NEAR(100 * integral / c.profile.size(), c.hct, 0.02 * c.hct) << name;
  }
  // More cells, less flow and a thinner layer.
  EXPECT_LT(r.cases.at("n100").re, r.cases.at("n50").re);
  EXPECT_LT(r.cases.at("n100").layer, r.cases.at("n50").layer);
  EXPECT_EQ(run_regression_check("cell_free_layer", r.quick_record, p.out_dir, std::cout), 0);
  // --collect reads the finished cases back and runs none: with n100's folder gone, n50 comes back
  // with the same numbers and n100 is left out (its rows "not run"), and no folder is made for it.
  fs::remove_all(fs::path(p.out_dir) / "n100");
  Params c = p;
  c.collect = true;
  const auto back = run(c);
  ASSERT_EQ(back.cases.size(), 1u);
  EXPECT_EQ(back.cases.at("n50").layer, r.cases.at("n50").layer);
  EXPECT_EQ(back.cases.at("n50").re, r.cases.at("n50").re);
  EXPECT_FALSE(fs::exists(fs::path(p.out_dir) / "n100"));
  fs::remove_all(p.out_dir);
}

}  // namespace
}  // namespace rbc
