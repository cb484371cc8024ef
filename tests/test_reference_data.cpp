// reference-data/: every table loads, every number has a tolerance with a reason, the checker's
// verdicts are right, and the study's cell-free channels pass their rows when rbcflow runs them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "reference/reference_table.hpp"
#include "channel_flow/channel_flow.hpp"
#include "scene/run_scene.hpp"

namespace rbc {
namespace {

TEST(ReferenceData, EveryTableLoadsAndEveryNumberHasAToleranceAndReason) {
  int numbers = 0;
  for (const char* name : {"channel_flow", "single_cell_migration", "four_cells_vs_disks", "cell_free_layer", "constriction"}) {
    const auto rows = load_reference_table(reference_table_path(name));
    EXPECT_FALSE(rows.empty()) << name;
    for (const auto& r : rows) {
      EXPECT_FALSE(r.source.empty()) << name << " " << r.id;
      if (r.kind == "number") {
        ++numbers;
        EXPECT_GT(r.tolerance, 0.0) << name << " " << r.id;
        EXPECT_FALSE(r.reason.empty()) << name << " " << r.id;
      }
    }
  }
  // SPEC section 5's bold numbers (21) plus the hematocrits and the cell-free channel rows.
  EXPECT_GE(numbers, 21);
}

TEST(ReferenceData, CheckerPassesWithinToleranceFailsOutsideAndSkipsWhatDidNotRun) {
  const std::vector<ReferenceRow> rows = {
      {"a", "quantity a", 10.0, "um", 0.5, "abs", "number", "Fig. 1", "r"},
      {"b", "quantity b", 2.0, "", 0.01, "rel", "number", "Fig. 1", "r"},
      {"c", "claim c", std::nullopt, "", 0, "claim", "claim", "Fig. 2", "r"},
      {"d", "not measured", 1.0, "", 0.1, "abs", "number", "Fig. 3", "r"},
  };
  std::ostringstream out;
  std::map<std::string, Measured> ours = {{"a", {10.4, {}, ""}}, {"b", {2.03, {}, ""}}, {"c", {{}, true, ""}}};
  const CheckSummary s = check_against_reference(rows, ours, out);
  EXPECT_EQ(s.passed, 2);
  EXPECT_EQ(s.failed, 1);  // b is 1.5 % off, tolerance 1 %
  EXPECT_EQ(s.not_run, 1);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(out.str().find("FAIL"), std::string::npos);
}

TEST(ReferenceData, MalformedTableIsRejectedNamingTheLine) {
  const auto path = std::filesystem::temp_directory_path() / "rbcflow_bad_table.csv";
  std::ofstream(path) << "id,quantity,value,unit,tolerance,tolerance_type,kind,source,reason\n"
                      << "x,\"q\",abc,um,0.1,abs,number,src,why\n";
  try {
    load_reference_table(path.string());
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(":2:"), std::string::npos) << e.what();
  }
}

// The study's narrow and wide channels without cells: the channel_flow experiment (quick
// parameters) against reference-data/channel_flow.csv.
TEST(ChannelFlowExperiment, CellFreeChannelsReproduceTheStudysMeanVelocityAndReynoldsNumber) {
  channel_flow::Params p;
  p.quick = true;
  p.progress = false;
  p.out_dir = (std::filesystem::temp_directory_path() / "rbcflow_channel_flow").string();
  const auto res = channel_flow::run(p);
  std::ostringstream table;
  const CheckSummary c = check_against_reference(load_reference_table(reference_table_path("channel_flow")), res.measured, table);
  std::printf("%s", table.str().c_str());
  EXPECT_EQ(c.failed, 0);
  EXPECT_EQ(c.passed, 4);
  // The profile is the parabola at the nodes (exact for the 5-point Laplacian), to round-off.
  for (const auto& [name, r] : res.channels) EXPECT_LT(r.profile_error, 1e-9) << name;
}

}  // namespace
}  // namespace rbc
