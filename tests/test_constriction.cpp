// The constriction experiment's quick case (2 ms, h = 0.625 um): its Hct row against the study
// and all its numbers against the committed regression record.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>

#include "constriction/constriction.hpp"

namespace rbc {
namespace {

TEST(ConstrictionExperiment, QuickRunMatchesItsRegressionRecordAndTheStudysHematocrit) {
  constriction::Params p;
  p.quick = true;
  p.progress = false;
  p.out_dir = (std::filesystem::temp_directory_path() / "rbcflow_constriction_quick").string();
  const auto r = constriction::run(p);
  EXPECT_NEAR(r.hematocrit, 4.74, 0.005);
  // Cell-free flux conservation survives the cells: U_narrow = 2 U_wide to the sections' spread.
  EXPECT_NEAR(r.u_narrow / r.u_wide, 2.0, 1e-3);
  EXPECT_EQ(run_reference_check("constriction", r.measured, p.out_dir, std::cout, false), 0);
  EXPECT_EQ(run_regression_check("constriction", r.quick_record, p.out_dir, std::cout), 0);
  std::filesystem::remove_all(p.out_dir);
}

// What make reproduce QUICK=1 does (paper/make_report.sh): the binary with an explicit --out, then
// the experiment's gnuplot script reading that folder. (A quick run that wrote elsewhere than
// --out left the script without data and failed CI.)
TEST(ConstrictionExperiment, QuickBinaryWritesWhereToldAndItsFiguresAreDrawn) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rbcflow_constriction_binary";
  std::filesystem::remove_all(dir);
  const std::string bin = std::string(RBCFLOW_BIN_DIR) + "/constriction";
  ASSERT_EQ(std::system((bin + " --quick --check --threads 1 --out " + dir.string() + " > " + dir.string() + ".log 2>&1").c_str()), 0);
  EXPECT_TRUE(std::filesystem::exists(dir / "run" / "snapshots.dat"));
  EXPECT_TRUE(std::filesystem::exists(dir / "check.md"));
  const std::string plot = "gnuplot -e \"dir='" + dir.string() + "'; figdir='" + dir.string() + "'\" " + RBCFLOW_SOURCE_DIR +
                           "/experiments/constriction/plot.gp > " + dir.string() + ".plot.log 2>&1";
  EXPECT_EQ(std::system(plot.c_str()), 0);
  for (const char* fig : {"constriction_membranes.png", "constriction_velocity.png", "constriction_centroids.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / fig)) << fig;
  std::filesystem::remove_all(dir);
}

// make evidence COLLECT=1 reads what is kept: with no finished run in the folder the collection
// runs nothing and every row says "not run" (it stopped with an error before).
TEST(ConstrictionExperiment, CollectWithoutAFinishedRunRunsNothingAndItsRowsAreNotRun) {
  constriction::Params p;
  p.collect = true;
  p.progress = false;
  p.out_dir = (std::filesystem::temp_directory_path() / "rbcflow_constriction_collect_empty").string();
  std::filesystem::remove_all(p.out_dir);
  const auto r = constriction::run(p);
  EXPECT_TRUE(r.collected_without_run);
  EXPECT_TRUE(r.measured.empty());
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::path(p.out_dir) / "run" / "series.csv"));
  const auto rows = load_reference_table(reference_table_path("constriction"));
  const CheckSummary s = compare_with_reference(rows, r.measured, {}, true);
  EXPECT_EQ(s.not_run, int(rows.size()));
  EXPECT_EQ(s.failed, 0);
  std::ostringstream out;
  EXPECT_EQ(run_reference_check("constriction", r.measured, p.out_dir, out, true), 0);
  std::filesystem::remove_all(p.out_dir);
}

}  // namespace
}  // namespace rbc
