// The stability_map experiment with its quick parameters (h = 0.5, 0.25 um; k_l x 0.1, 1, 10;
// k_b x 1000; both couplings; the extreme cases): every limit and outcome against the committed
// regression record of that quick map. The study publishes no stability numbers, so the record
// is the only check; the full map is `build/bin/stability_map --check` (make reproduce).
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

#include "reference/regression_record.hpp"
#include "stability_map/stability_map.hpp"

namespace rbc {
namespace {

TEST(StabilityMapExperiment, QuickMapMatchesItsRegressionRecord) {
  auto p = stability_map::Params::quick_params();
  p.progress = false;
  p.out_dir = (std::filesystem::temp_directory_path() / "rbcflow_stability_map_quick").string();
  const auto r = stability_map::run(p);
  EXPECT_EQ(run_regression_check("stability_map", r.quick_record, p.out_dir, std::cout), 0);
  // The explicit limit falls as the springs stiffen (k_l x 0.1, 1, 10), at each h.
  for (const char* h : {"0.5", "0.25"}) {
    const std::string e = std::string("explicit_h") + h;
    EXPECT_GT(r.quick_record.at(e + "_kl0.1_kb1").value, r.quick_record.at(e + "_kl1_kb1").value) << h;
    EXPECT_GT(r.quick_record.at(e + "_kl1_kb1").value, r.quick_record.at(e + "_kl10_kb1").value) << h;
  }
}

}  // namespace
}  // namespace rbc
