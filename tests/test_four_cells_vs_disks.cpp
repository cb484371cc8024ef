// The four_cells_vs_disks experiment's quick case (5 ms, h = 0.625 um): its numbers against the
// committed regression record, the scenes it builds, and its cases run through GNU parallel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "common/case_runner.hpp"
#include "four_cells_vs_disks/four_cells_vs_disks.hpp"
#include "io/csv.hpp"

namespace rbc {
namespace {

namespace fs = std::filesystem;
using namespace four_cells_vs_disks;

TEST(WorkPrecision, RichardsonCentroidsTakeTheCoarseRunToTheNearestImage) {
  // 2 c(Δt) − c(2Δt) body by body; a body that crossed the periodic seam between the two runs
  // (x1 = 1 um in the fine run, 99 um in the coarse one, L = 100 um) is extrapolated across it,
  // not through the channel: 2 × 1 − (−1) = 3 um.
  const double L = 100e-6;
  const std::vector<Eigen::Vector2d> fine = {{1e-6, 10e-6}, {50e-6, 20e-6}}, coarse = {{99e-6, 11e-6}, {49e-6, 20.5e-6}};
  const auto r = case_runner::richardson_centroids(fine, coarse, L);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_NEAR(r[0].x(), 3e-6, 1e-18);
  EXPECT_NEAR(r[0].y(), 9e-6, 1e-18);
  EXPECT_NEAR(r[1].x(), 51e-6, 1e-18);
  EXPECT_NEAR(r[1].y(), 19.5e-6, 1e-18);
  // An exact first-order error e Δt is removed: c(Δt) = c0 + e Δt, c(2Δt) = c0 + 2 e Δt.
  const std::vector<Eigen::Vector2d> c0 = {{20e-6, 5e-6}};
  const Eigen::Vector2d e(0.3e-6, -0.2e-6);
  const auto exact = case_runner::richardson_centroids({c0[0] + e}, {c0[0] + 2 * e}, L);
  EXPECT_NEAR((exact[0] - c0[0]).norm(), 0.0, 1e-18);
}

// make reproduce runs --study-only: each case's reported Δt run, the one its rows and figures read;
// the level below it (the k_b cells at 0.75 us, the 1000 k_b ones at 0.375 us) is make evidence's
// (the quick parameters keep their cases).
TEST(FourCellsVsDisksExperiment, StudyOnlyIsEachCasesReportedDtRunAndTheCoarseConvergenceRuns) {
  Params p;
  p.study_only = true;
  std::set<std::string> names;
  int coarse_convergence = 0;
  for (const Case& c : cases(p)) {
    if (c.role == "convergence") {  // the error against run time on the coarse mesh (case_runner.hpp)
      EXPECT_GE(c.h, case_runner::kReportConvergenceMinH) << c.name;
      ++coarse_convergence;
      continue;
    }
    names.insert(c.name);
    EXPECT_TRUE(c.reported) << c.name;
  }
  EXPECT_EQ(names, (std::set<std::string>{"kb1_dt1.5us", "kb10_dt1.5us", "kb100_dt1.5us", "kb1000_dt0.75us", "s07_dt1.5us", "disks_dt1.5us"}));
  EXPECT_EQ(coarse_convergence, 13);  // cells explicit 2, semi-implicit 4, extrapolated 3, disks 4, at h = 0.625 um
  Params evidence;
  std::set<std::string> finer;
  for (const Case& c : cases(evidence))
    if (c.name.find("_dt0.") != std::string::npos && !c.reported && c.role != "paired") finer.insert(c.name);
  EXPECT_EQ(finer, (std::set<std::string>{"kb1_dt0.75us", "kb1000_dt0.375us"}));
  Params quick;
  quick.quick = true;
  const auto all_quick = cases(quick);
  quick.study_only = true;
  EXPECT_EQ(cases(quick).size(), all_quick.size());
}

// The k_b row from its paired starts (the study's places and seeds 1-5 at 0.75, 1.5 and 3 us, no
// 6 us ensemble): the Δt part fits the six starts' level means, the start spread is theirs pooled
// over the levels (the same s as the fit's noise), and nothing is missing, so the row's u_num is
// measured, not recorded. Without the paired starts the same cases leave the start ensemble missing.
TEST(FourCellsVsDisksExperiment, PairedStartsGiveTheRowsDtPartAndItsStartSpread) {
  Params p;
  p.out_dir = (fs::temp_directory_path() / "rbcflow_paired_row_none").string();  // no series: no window part
  Results res;
  const std::vector<double> offsets = {0.0, 0.02, -0.01, 0.015, -0.03, 0.005};  // um, start s = 0..5
  const std::vector<double> level_mean = {9.10, 9.15, 9.20};                     // um at kPairedDts
  const std::vector<double> level_scale = {1.0, 1.0, 4.0};                       // the 3 us level's starts spread more
  for (std::size_t l = 0; l < kPairedDts.size(); ++l)
    for (unsigned s = 0; s < offsets.size(); ++s) {
      CaseResult c;
      char name[64];
      if (s == 0)
        std::snprintf(name, sizeof name, "kb1_dt%gus", kPairedDts[l] * 1e6);
      else
        std::snprintf(name, sizeof name, "kb1_seed%u_dt%gus", s, kPairedDts[l] * 1e6);
      c.spec.name = name;
      c.dt = kPairedDts[l];
      c.h = 0.3125e-6;
      c.distance = (level_mean[l] + level_scale[l] * offsets[s]) * 1e-6;
      c.reynolds = 2.71;
      res.cases[name] = c;
    }
  const Measured m = row_with_uncertainty(p, res, "kb1", false, "");
  ASSERT_TRUE(m.value);
  EXPECT_NEAR(*m.value, 9.15, 1e-9);  // the reported run: the study's places at 1.5 us
  ASSERT_TRUE(m.u.dt);
  EXPECT_EQ(m.u.dt->values.size(), 3u);
  ASSERT_TRUE(m.u.ensemble);
  EXPECT_NEAR(*m.u.ensemble, sample_std(offsets) * std::sqrt((1.0 + 1.0 + 16.0) / 3), 1e-9);  // pooled: the 3 us level's too
  EXPECT_EQ(m.u.members, 6);
  EXPECT_TRUE(m.u.missing.empty()) << m.u.missing;
  EXPECT_TRUE(m.u.total());
  // Seed 5 missing at one level: no paired starts beyond the finished ones; with four of five seeds
  // the pairing still holds.
  res.cases.erase("kb1_seed5_dt3us");
  const Measured four = row_with_uncertainty(p, res, "kb1", false, "");
  EXPECT_EQ(four.u.members, 5);
  // Only the study's places: the 6 us ensemble is what is left, and it is missing.
  for (unsigned s = 1; s <= 5; ++s)
    for (double dt : kPairedDts) {
      char name[64];
      std::snprintf(name, sizeof name, "kb1_seed%u_dt%gus", s, dt * 1e6);
      res.cases.erase(name);
    }
  const Measured alone = row_with_uncertainty(p, res, "kb1", false, "");
  EXPECT_FALSE(alone.u.ensemble);
  EXPECT_NE(alone.u.missing.find("start ensemble"), std::string::npos) << alone.u.missing;
}

TEST(FourCellsVsDisksExperiment, CasesBuildTheStudysBodiesAndOnlyThose) {
  Params p;
  const auto all = cases(p);
  int study = 0, validation = 0;
  std::map<std::string, int> at_reynolds;  // the validation cases per Re0 of their channel
  std::set<std::string> names;
  for (const Case& c : all) names.insert(c.name);
  for (const Case& c : all) {
    const Scene s = case_scene(c, false);
    if (c.role == "validation") {  // one disk, d = W/4 at 0.4 W in a channel W x W (Pan & Glowinski 2002)
      ++validation;
      ASSERT_EQ(s.disks.size(), 1u) << c.name;
      EXPECT_TRUE(s.cells.empty()) << c.name;
      EXPECT_DOUBLE_EQ(s.disks[0].radius, s.height / 8) << c.name;
      EXPECT_DOUBLE_EQ(s.disks[0].center.y(), 0.4 * s.height) << c.name;
      EXPECT_DOUBLE_EQ(s.length, s.height) << c.name;
      EXPECT_EQ(s.dt, c.dt) << c.name;
      ASSERT_TRUE(s.reynolds0.has_value()) << c.name;
      ++at_reynolds[case_runner::num(*s.reynolds0)];
      // Their Re 96.74 as the scene file has it (to 1.2 ms); 12.78 to 8 ms, 201 samples.
      EXPECT_EQ(s.end, *s.reynolds0 == 13.91 ? 8e-3 : 1.2e-3) << c.name;
      if (*s.reynolds0 == 13.91) {
        EXPECT_DOUBLE_EQ(s.output_every, 4e-5) << c.name;
      }
      continue;
    }
    EXPECT_EQ(s.cells.size() + s.disks.size(), 4u) << c.name;
    EXPECT_TRUE(s.cells.empty() || s.disks.empty()) << c.name;  // a scene builds only what it uses
    // Disks need the study's form; the k_b cells' incremental-form ladder and the extrapolated
    // scheme's work-precision runs (conv_sie_*, its second-order form) alone take the other, and
    // only those runs the extrapolated scheme.
    const bool extrapolated = c.name.rfind("conv_sie_", 0) == 0;
    EXPECT_EQ(s.projection, c.name.rfind("kb1_inc_dt", 0) == 0 || extrapolated ? "incremental" : "study") << c.name;
    EXPECT_EQ(s.scheme, extrapolated ? "lie-extrapolated" : "lie") << c.name;
    if (c.role != "study") continue;
    ++study;
    EXPECT_EQ(s.mesh_size, 0.3125e-6);
    EXPECT_EQ(s.end, 0.2);
    for (std::size_t k = 0; k < 4; ++k) {  // the study's places, exactly
      const Eigen::Vector2d at = c.disks ? s.disks[k].center : s.cells[k].center;
      EXPECT_EQ(at.x(), kPlaces[k][0]);
      EXPECT_EQ(at.y(), kPlaces[k][1]);
    }
  }
  EXPECT_EQ(study, 6);
  // Pan & Glowinski's two cases: four Δt and two coarser h at each, their Re0 106.09 and 13.91.
  EXPECT_EQ(validation, 12);
  EXPECT_EQ(at_reynolds, (std::map<std::string, int>{{"106.09", 6}, {"13.91", 6}}));
  for (const char* kept : {"pg2002_h128_dt1.25e-08", "pg2002_h128_dt2.5e-08", "pg2002_h128_dt5e-08", "pg2002_h128_dt1e-07",
                           "pg2002_h64_dt1.25e-08", "pg2002_h32_dt1.25e-08"})  // the kept runs' names (paper/evidence/data/)
    EXPECT_TRUE(names.count(kept)) << kept;
  // Every study case has its Δt sequence (u_num's Δt part): 6, 3 and 1.5 us.
  for (const char* base : {"kb1", "kb10", "kb100", "kb1000", "s07", "disks"})
    for (const char* suffix : {"", "_dt3us", "_dt1.5us"}) EXPECT_TRUE(names.count(std::string(base) + suffix)) << base << suffix;
  // The incremental form's ladder: the k_b cells from the study's places at each of its Δt.
  for (double dt : kIncrementalDts) {
    char name[32];
    std::snprintf(name, sizeof name, "kb1_inc_dt%gus", dt * 1e6);
    const auto it = std::find_if(all.begin(), all.end(), [&](const Case& x) { return x.name == name; });
    ASSERT_NE(it, all.end()) << name;
    const Scene s = case_scene(*it, false);
    EXPECT_EQ(s.dt, dt) << name;
    EXPECT_EQ(s.cells.size(), 4u) << name;
    EXPECT_EQ(s.cells[0].kb_scale, 1.0) << name;
    EXPECT_EQ(s.cells[0].center.x(), kPlaces[0][0]) << name;
  }
  // A perturbed start moves every centre, by at most kPerturbation in each direction.
  Case c;
  c.name = "kb1_seed1";
  c.seed = 1;
  const Scene s = case_scene(c, false);
  for (std::size_t k = 0; k < 4; ++k) {
    const double dx = s.cells[k].center.x() - kPlaces[k][0], dy = s.cells[k].center.y() - kPlaces[k][1];
    EXPECT_GT(std::abs(dx) + std::abs(dy), 0.0);
    EXPECT_LE(std::abs(dx), kPerturbation);
    EXPECT_LE(std::abs(dy), kPerturbation);
  }
}

TEST(FourCellsVsDisksExperiment, QuickRunMatchesItsRegressionRecord) {
  Params p;
  p.quick = true;
  p.progress = false;
  p.threads = 1;
  p.out_dir = (fs::temp_directory_path() / "rbcflow_four_cells_quick").string();
  fs::remove_all(p.out_dir);
  const auto r = run(p);
  for (const auto& [name, c] : r.cases) EXPECT_TRUE(c.failure.empty()) << name << ": " << c.failure;
  // In 5 ms every case has started toward the centreline, the s* = 0.7 cells the most.
  for (const auto& [name, c] : r.cases) {
    double start = 0;
    for (double y : c.y.front()) start += std::abs(y - 25e-6) / 4;
    EXPECT_LT(c.distance, start) << name;
  }
  EXPECT_LT(r.cases.at("s07").distance, r.cases.at("kb1").distance);
  // The stiffest cells stay rounder than the softest.
  auto mean4 = [](const std::array<double, 4>& a) { return (a[0] + a[1] + a[2] + a[3]) / 4; };
  EXPECT_GT(mean4(r.cases.at("kb1000").circularity_end), mean4(r.cases.at("kb1").circularity_end));
  EXPECT_EQ(run_regression_check("four_cells_vs_disks", r.quick_record, p.out_dir, std::cout), 0);
  fs::remove_all(p.out_dir);
}

std::string without_wall_time(const fs::path& csv) {  // cases.csv minus its steps and wall columns
  std::ifstream in(csv);
  std::ostringstream out;
  for (std::string line; std::getline(in, line);) {
    std::stringstream ss(line);
    std::string field;
    for (int k = 0; std::getline(ss, field, ','); ++k)
      if (k != 9) out << field << ",";
    out << "\n";
  }
  return out.str();
}

// The sweep path of make reproduce and the README: the cases through GNU parallel (--only, one
// thread each), then --check --reuse, give the table of one process running every case.
TEST(FourCellsVsDisksExperiment, CasesThroughGnuParallelGiveTheTableOfOneProcess) {
  if (std::system("parallel --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "GNU parallel not installed (make deps)";
  const fs::path one = fs::temp_directory_path() / "rbcflow_four_cells_one", par = fs::temp_directory_path() / "rbcflow_four_cells_par";
  fs::remove_all(one);
  fs::remove_all(par);
  const std::string bin = std::string(RBCFLOW_BIN_DIR) + "/four_cells_vs_disks";
  ASSERT_EQ(std::system((bin + " --quick --check --threads 1 --out " + one.string() + " > " + one.string() + ".log 2>&1").c_str()), 0);
  const std::string sweep = bin + " --quick --list-cases | parallel --will-cite -j 2 " + bin + " --quick --only {} --threads 1 --out " +
                            par.string() + " '>' /dev/null '2>&1'";
  ASSERT_EQ(std::system(sweep.c_str()), 0);
  ASSERT_EQ(std::system((bin + " --quick --check --reuse --out " + par.string() + " > " + par.string() + ".log 2>&1").c_str()), 0);
  EXPECT_EQ(without_wall_time(one / "cases.csv"), without_wall_time(par / "cases.csv"));
  EXPECT_FALSE(without_wall_time(one / "cases.csv").empty());
  // The figures are drawn from the collected folder.
  const std::string plot = "gnuplot -e \"dir='" + par.string() + "'; figdir='" + par.string() + "'\" " + RBCFLOW_SOURCE_DIR +
                           "/experiments/four_cells_vs_disks/plot.gp > " + par.string() + ".plot.log 2>&1";
  EXPECT_EQ(std::system(plot.c_str()), 0);
  for (const char* fig : {"four_cells_vs_disks_membranes.png", "four_cells_vs_disks_heights.png", "four_cells_vs_disks_distance.png"})
    EXPECT_TRUE(fs::exists(par / fig)) << fig;
  fs::remove_all(one);
  fs::remove_all(par);
}

// The disk's migration-rate rows read Pan & Glowinski's trajectories at their digitized points:
// each row's value is the point nearest its nominal distance travelled, to the row's 4 digits.
TEST(FourCellsVsDisksExperiment, DiskTrajectoryRowsAreTheirDigitizedPoints) {
  const auto rows = load_reference_table(reference_table_path("disk_validation"));
  for (const DiskValidation& pg : kDiskValidations) {
    const auto points = read_csv_table(reference_table_path(pg.trajectory), {"s_over_W", "x2_over_W"});
    ASSERT_GE(points.size(), 10u) << pg.trajectory;
    for (const auto& [id, nominal] : pg.travel) {
      const auto row = std::find_if(rows.begin(), rows.end(), [&](const ReferenceRow& r) { return r.id == id; });
      ASSERT_NE(row, rows.end()) << id;
      const CsvRecord& nearest = nearest_digitized_point(points, nominal);
      EXPECT_NEAR(*row->value, csv_number(nearest, 1, "x2_over_W"), 5e-5) << id;
      // The point is the nearest: no other lies closer to the nominal distance.
      const double s = csv_number(nearest, 0, "s_over_W");
      for (const CsvRecord& p : points) EXPECT_GE(std::abs(csv_number(p, 0, "s_over_W") - nominal), std::abs(s - nominal)) << id;
    }
    EXPECT_NE(std::find_if(rows.begin(), rows.end(), [&](const ReferenceRow& r) { return r.id == pg.equilibrium_id; }), rows.end())
        << pg.equilibrium_id;
  }
}

}  // namespace
}  // namespace rbc
