// The constriction experiment's quick case (2 ms, h = 0.625 um): its Hct row against the study
// and all its numbers against the committed regression record.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
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

}  // namespace
}  // namespace rbc
