// The constriction experiment's quick case (2 ms, h = 0.625 um): its Hct row against the study
// and all its numbers against the committed regression record.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

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

}  // namespace
}  // namespace rbc
