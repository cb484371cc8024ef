// The single_cell_migration experiment with its quick parameters (h = 0.25 um, to 1 ms): the
// properties a broken coupling, kernel or membrane force would fail. The full-length comparison
// with the study is `build/bin/single_cell_migration --check` (make reproduce).
#include <gtest/gtest.h>

#include <filesystem>

#include "single_cell_migration/single_cell_migration.hpp"

namespace rbc {
namespace {

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
}

}  // namespace
}  // namespace rbc
