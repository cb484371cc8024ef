// The single_cell_migration experiment with its quick parameters (h = 0.25 um, to 1 ms): the
// properties a broken coupling, kernel or membrane force would fail. The full-length comparison
// with the study is `build/bin/single_cell_migration --check` (make reproduce).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "reference/regression_record.hpp"
#include "single_cell_migration/single_cell_migration.hpp"

namespace rbc {
namespace {

// make reproduce runs --study-only: the narrow and wide channels under the chosen reading, and the
// error against run time (conv_*, 25 short runs: 21 of the two couplings, 4 of the extrapolated scheme).
TEST(SingleCellMigrationExperiment, StudyOnlyIsTheNarrowAndWideRunsAndTheErrorAgainstRunTime) {
  single_cell_migration::Params p;
  p.study_only = true;
  std::vector<std::string> names = single_cell_migration::case_names(p), study;
  std::sort(names.begin(), names.end());
  for (const std::string& n : names)
    if (n.rfind("conv_", 0) != 0) study.push_back(n);
  EXPECT_EQ(study, (std::vector<std::string>{"narrow_si_s055", "narrow_si_s070", "narrow_si_s100", "wide_si_s055", "wide_si_s070", "wide_si_s100"}));
  EXPECT_EQ(names.size() - study.size(), 25u);
}

TEST(SingleCellMigrationExperiment, QuickRunMigratesTowardTheCentrelineAndDeformsAsTheStudyDescribes) {
  auto p = single_cell_migration::Params::quick_params();
  p.progress = false;
  p.out_dir = (std::filesystem::temp_directory_path() / "rbcflow_scm_quick").string();
  const auto r = single_cell_migration::run(p);
  auto c = [&](const char* s) -> const single_cell_migration::Case& { return r.cases.at(std::string("narrow_si_") + s); };
  for (const char* s : {"s055", "s070", "s100"}) {
    ASSERT_TRUE(c(s).failure.empty()) << c(s).failure;
    const auto& cell = c(s).summary.cells.at(0);
    // Released at 3 um, the cell rises toward the centreline (5 um) without crossing it far.
    EXPECT_GT(cell.centroid.y(), 3.5e-6) << s;
    EXPECT_LT(cell.centroid.y(), 5.5e-6) << s;
    // The incompressible flow holds the area: the immersed boundary leaks less than 0.1 %.
    EXPECT_LT(std::abs(cell.area_drift), 1e-3) << s;
    // A cell in the channel lowers the flow rate: Re below the cell-free Re0.
    EXPECT_LT(c(s).summary.reynolds, 0.5556) << s;
    EXPECT_GT(c(s).summary.reynolds, 0.40) << s;
  }
  // Deflated cells deform strongly; the swollen s* = 1 cell is the slowest to migrate.
  EXPECT_EQ(c("s055").summary.cells[0].shape.kind, "parachute");
  EXPECT_LT(c("s100").summary.cells[0].centroid.y(), c("s055").summary.cells[0].centroid.y());
  EXPECT_LT(c("s100").summary.cells[0].centroid.y(), c("s070").summary.cells[0].centroid.y());
  // The hematocrit rows are geometry: they pass for the prepared shapes s* = 0.55 and 0.7.
  EXPECT_NEAR(r.measured.at("hct_s055").value.value(), 6.77, 0.005);
  EXPECT_NEAR(r.measured.at("hct_s07").value.value(), 8.62, 0.005);
  // The study's rows a quick run measures: no FAIL (s* = 1's hematocrit is a recorded deviation).
  const auto study = compare_with_reference(load_reference_table(reference_table_path("single_cell_migration")), r.measured,
                                            load_known_deviations(known_deviations_path("single_cell_migration")), false);
  EXPECT_TRUE(study.ok());
  EXPECT_EQ(study.deviations, 1);
  // The quick case's own numbers against its committed record (reference-data/regression/).
  EXPECT_EQ(run_regression_check("single_cell_migration", r.quick_record, p.out_dir, std::cout), 0);
}

// The regression record can fail: bending 10 % stiffer (one cell, s* = 0.55) moves the quick
// case's height, shape and Re out of their round-off bands.
TEST(SingleCellMigrationExperiment, TenPercentStifferBendingTurnsTheQuickRegressionCheckRed) {
  auto p = single_cell_migration::Params::quick_params();
  p.progress = false;
  p.swelling_ratios = {0.55};
  p.membrane.kb *= 1.1;
  p.out_dir = (std::filesystem::temp_directory_path() / "rbcflow_scm_quick_kb").string();
  const auto r = single_cell_migration::run(p);
  std::vector<RegressionRow> rows;
  for (const auto& row : load_regression_record(regression_record_path("single_cell_migration")))
    if (row.id.ends_with("_s055") && !row.id.starts_with("hct0")) rows.push_back(row);  // the prepared shape does not see k_b much
  ASSERT_EQ(rows.size(), 6u);
  std::ostringstream reg;
  const RegressionSummary rs = compare_with_record(rows, r.quick_record, reg);
  std::printf("%s", reg.str().c_str());
  EXPECT_EQ(rs.failed, 6) << "every dynamic row of the s* = 0.55 cell must leave its band";
}

}  // namespace
}  // namespace rbc
