// reference-data/: every table loads, every number has a tolerance with a reason, the checker's
// verdicts are right, and the study's cell-free channels pass their rows when rbcflow runs them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "reference/recorded_uncertainty.hpp"
#include "reference/reference_table.hpp"
#include "reference/regression_record.hpp"
#include "channel_flow/channel_flow.hpp"
#include "scene/run_scene.hpp"

namespace rbc {
namespace {

// A measured number whose u_num is known (0: a checker test about the tolerance alone).
Measured measured(double v, double u = 0) {
  Measured m{v, {}, ""};
  m.u.other_value = u;
  return m;
}

TEST(ReferenceData, EveryTableLoadsAndEveryNumberHasAToleranceAndReason) {
  int numbers = 0;
  for (const char* name : {"channel_flow", "single_cell_migration", "four_cells_vs_disks", "cell_free_layer", "constriction", "disk_validation"}) {
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
  // The study's 21 published results of its Sec. 3 plus the hematocrits and the cell-free channel rows.
  EXPECT_GE(numbers, 21);
}

// A tolerance comes from the study alone and must let the verdict tell its cases apart.
TEST(ReferenceData, NoWindowHoldsTheStudyValueOfACaseTheStudyTellsItApartFrom) {
  int pairs = 0;
  for (const char* name : {"channel_flow", "single_cell_migration", "four_cells_vs_disks", "cell_free_layer", "constriction"}) {
    const auto rows = load_reference_table(reference_table_path(name));
    for (const auto& r : rows)
      for (const std::string& other : r.apart_from) {
        const auto o = std::find_if(rows.begin(), rows.end(), [&](const ReferenceRow& x) { return x.id == other; });
        ASSERT_NE(o, rows.end()) << name << ": " << r.id << " is told apart from '" << other << "', not a row";
        ASSERT_TRUE(r.value && o->value) << name << ": " << r.id;
        const double allowed = r.tolerance_type == "rel" ? r.tolerance * std::abs(*r.value) : r.tolerance;
        EXPECT_LT(allowed, std::abs(*o->value - *r.value)) << name << ": the window of " << r.id << " holds the study's " << other;
        ++pairs;
      }
  }
  EXPECT_GE(pairs, 30);  // the distances and Re of the four cells and disks, the single cells' Re, the layers, narrow/wide
}

TEST(ReferenceData, UnresolvedWhenOurUncertaintyIsLargerThanTheToleranceAndReachesTheWindow) {
  const std::vector<ReferenceRow> rows = {{"d", "distance", 9.22, "um", 0.08, "abs", "number", "Fig. 6", "r", ""}};
  auto with_u = [](double v, std::optional<double> u) {
    Measured m{v, {}, ""};
    if (u) m.u.other_value = u;
    return std::map<std::string, Measured>{{"d", m}};
  };
  // Within the tolerance and u_num below it: PASS.
  EXPECT_EQ(compare_with_reference(rows, with_u(9.25, 0.05), {}, true).passed, 1);
  // Within the tolerance, but u_num above it: UNRESOLVED, not a failure.
  CheckSummary s = compare_with_reference(rows, with_u(9.25, 0.2), {}, true);
  EXPECT_EQ(s.unresolved, 1);
  EXPECT_TRUE(s.ok());
  EXPECT_EQ(s.rows[0].u_num, "0.2");
  // Outside the tolerance, but ours ± u_num reaches it: UNRESOLVED.
  EXPECT_EQ(compare_with_reference(rows, with_u(9.45, 0.2), {}, true).unresolved, 1);
  // Outside the tolerance by more than u_num: decided, and not recorded: FAIL.
  EXPECT_EQ(compare_with_reference(rows, with_u(9.60, 0.2), {}, true).failed, 1);
  // u_num not measured: our numerics cannot decide a row near the window.
  s = compare_with_reference(rows, with_u(9.25, std::nullopt), {}, true);
  EXPECT_EQ(s.unresolved, 1);
  EXPECT_EQ(s.rows[0].u_num, "not measured");
  // Parts of u_num whose evidence runs are missing: it cannot clear the row either.
  auto partial = with_u(9.25, 0.01);
  partial["d"].u.missing = "the Δt sequence";
  s = compare_with_reference(rows, partial, {}, true);
  EXPECT_EQ(s.unresolved, 1);
  EXPECT_EQ(s.rows[0].u_num, "0.01 (incomplete)");
}

// Beside u_num's parts, the u_num a run one Δt level coarser would have, against the tolerance.
TEST(ReferenceData, ACoarserDtIsSaidToDoOnlyWhereItsUncertaintyStaysWithinTheTolerance) {
  // f = 3 + 0.5 Δt at Δt = 1, 2, 4 (first order, exact): U 0.625 at the finest, 1.25 at 2 Δt
  // (Fs 1.25 times its error 1.0); reported: the finest.
  const double coarser = grid_convergence_index({3.5, 4.0, 5.0}, 2, 1, 1).u;
  ASSERT_NEAR(coarser, 1.25, 1e-12);
  auto table = [](double tolerance, int reported, std::string missing) {
    const std::vector<ReferenceRow> rows = {{"d", "distance", 3.0, "um", tolerance, "abs", "number", "Fig. 6", "r", ""}};
    Measured m{3.5, {}, ""};
    m.u.dt = grid_convergence_index({3.5, 4.0, 5.0}, 2, 1, reported);
    m.u.missing = missing;
    return compare_with_reference(rows, {{"d", m}}, {}, true).rows[0].u_parts;
  };
  EXPECT_NE(table(2.0, 0, "").find("; a coarser Δt: at 2 Δt u_num 1.2, within the tolerance: that Δt would do"), std::string::npos)
      << table(2.0, 0, "");
  EXPECT_NE(table(1.0, 0, "").find("; a coarser Δt: at 2 Δt u_num 1.2, above the tolerance"), std::string::npos) << table(1.0, 0, "");
  // Reported at 2 Δt: U 1.25 there; at 4 Δt (Fs 1.25 times 2.0) 2.5.
  EXPECT_NE(table(2.0, 1, "").find("at 2 Δt u_num 2.5, above the tolerance"), std::string::npos) << table(2.0, 1, "");
  // The coarsest level reported, or u_num incomplete: nothing to say.
  EXPECT_EQ(table(2.0, 2, "").find("coarser Δt"), std::string::npos);
  EXPECT_EQ(table(2.0, 0, "the h levels").find("coarser Δt"), std::string::npos);
  // A chaotic row (its members' mean): the other parts kept as they are, 2 s/√n = 2 (0.3/√4) = 0.3
  // beside the coarser Δt part 1.25: u_num √(1.25² + 0.3²) = 1.29.
  const std::vector<ReferenceRow> rows = {{"cfl", "layer", 3.0, "um", 1.28, "abs", "number", "Sec. 3", "r", ""}};
  Measured m;
  for (double v : {3.2, 3.5, 3.8, 3.5}) m.ensemble.push_back({"seed", v});
  m.u.ensemble = 0.3;
  m.u.members = 4;
  m.u.of_mean = true;
  m.u.dt = grid_convergence_index({3.5, 4.0, 5.0}, 2, 1, 0);
  NumericalUncertainty at_coarser = m.u;
  at_coarser.dt = grid_convergence_index({3.5, 4.0, 5.0}, 2, 1, 1);
  ASSERT_NEAR(*at_coarser.total(), std::hypot(1.25, 0.3), 1e-12);
  const std::string parts = compare_with_reference(rows, {{"cfl", m}}, {}, true).rows[0].u_parts;
  EXPECT_NE(parts.find("at 2 Δt u_num 1.3, above the tolerance"), std::string::npos) << parts;  // 1.29 > 1.28
}

TEST(Uncertainty, GridConvergenceIndexFindsTheOrderAndTheLimitOfAFirstOrderSequence) {
  // f = 3 + 0.5 Δt at Δt = 1, 2, 4: order 1 (ln(1/0.5)/ln 2), exact δ_RE; the few-points σ is
  // min(σ_1, σ_2) = 0 (the data lie on δ_1); Fs 1.25; U = 1.25 |f_fit(1) − 3| = 0.625, limit 3.
  RefinementUncertainty u = grid_convergence_index({3.5, 4.0, 5.0}, 2, 1);
  EXPECT_EQ(u.levels, 3);
  EXPECT_NEAR(u.observed_order, 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(u.safety_factor, 1.25);
  EXPECT_NEAR(u.u, 0.625, 1e-12);
  EXPECT_NEAR(u.extrapolated, 3.0, 1e-12);
  // Second order observed in a first-order scheme (f = 1 + 0.25 Δt²): p = 2 is above p_hi = 1, so
  // the fixed-order fits decide; δ_2 fits exactly (σ 0; δ_1's σ is 0.40), limit 1, ε = 0.25, and
  // Fs 3 for an order outside [0.25, 1.05): U = 3 · 0.25.
  u = grid_convergence_index({1.25, 2.0, 5.0}, 2, 1);
  EXPECT_NEAR(u.observed_order, 2.0, 1e-12);
  EXPECT_EQ(u.fit, RefinementFit::FixedHigh);
  EXPECT_DOUBLE_EQ(u.safety_factor, 3.0);
  EXPECT_NEAR(u.extrapolated, 1.0, 1e-12);
  EXPECT_NEAR(u.u, 0.75, 1e-12);
  // Two levels: the formal order and Fs 3, 3 |4.0 − 3.5| / (2 − 1).
  EXPECT_NEAR(grid_convergence_index({3.5, 4.0}, 2, 1).u, 1.5, 1e-12);
  // Oscillating: no order; δ_1 (f = 3.6 + Δt/14, residuals −6/35, 9/35, −3/35, σ = sqrt(126/1225))
  // fits better than δ_2 (σ 0.34); σ ≥ Δ_φ = (4.0 − 3.5)/2, so U = 3 σ/Δ_φ (ε + σ + |res|) with
  // ε = 1/14 and |res| = 6/35: noise, no convergence observed.
  u = grid_convergence_index({3.5, 4.0, 3.8}, 2, 1);
  EXPECT_FALSE(std::isfinite(u.observed_order));
  EXPECT_EQ(u.fit, RefinementFit::FixedLow);
  EXPECT_TRUE(u.noise_dominated);
  const double sigma = std::sqrt(126.0 / 1225.0);
  EXPECT_NEAR(u.fit_sigma, sigma, 1e-12);
  EXPECT_NEAR(u.u, 3 * sigma / 0.25 * (1.0 / 14 + sigma + 6.0 / 35), 1e-12);
  EXPECT_NEAR(u.extrapolated, 3.6, 1e-12);
  // An order far outside the formal one (pre-asymptotic, p = ln(1.03/0.09)/ln 2 = 3.5): Fs 3.
  EXPECT_DOUBLE_EQ(grid_convergence_index({12.19, 12.28, 13.31}, 2, 1).safety_factor, 3.0);
  EXPECT_THROW(grid_convergence_index({1.0}, 2, 1), std::invalid_argument);
  EXPECT_THROW(grid_convergence_index({1.0, 2.0}, 1, 1), std::invalid_argument);
  EXPECT_THROW(grid_convergence_index({1.0, 2.0}, 2, 0), std::invalid_argument);
}

TEST(Uncertainty, GridConvergenceIndexOfTheSecondFinestRunIsItsDistanceToTheLimitWithTheSafetyFactor) {
  // f = 3 + 0.5 Δt at Δt = 1, 2, 4, reported at Δt = 2 (the Δt = 1 run is evidence only):
  // U = Fs ε_1 = 1.25 |f_fit(2) − 3| = 1.25, i.e. Fs times f2's distance 1.0 to the limit.
  const RefinementUncertainty u = grid_convergence_index({3.5, 4.0, 5.0}, 2, 1, 1);
  EXPECT_EQ(u.reported, 1);
  EXPECT_NEAR(u.u, 1.25 * (4.0 - 3.0), 1e-12);
  EXPECT_NEAR(u.extrapolated, 3.0, 1e-12);
  EXPECT_NE(u.describe().find("of the second finest"), std::string::npos);
  // Reported at the coarsest level (a row run at Δt = 4 with two finer evidence runs): U = 1.25
  // |f_fit(4) − 3| = 2.5; a level beyond those given is refused.
  EXPECT_NEAR(grid_convergence_index({3.5, 4.0, 5.0}, 2, 1, 2).u, 1.25 * (5.0 - 3.0), 1e-12);
  EXPECT_THROW(grid_convergence_index({3.5, 4.0, 5.0}, 2, 1, 3), std::invalid_argument);
}

TEST(Uncertainty, WindowNoiseIsTheSpreadOfTheLastWindowsMeansAndPartsAddInQuadrature) {
  std::vector<double> t, v;
  for (int k = 1; k <= 50; ++k) {
    t.push_back(k * 0.1);
    v.push_back((k - 1) / 10 % 2 ? 1.0 : 0.0);  // windows of 10 samples alternate 0, 1
  }
  EXPECT_NEAR(window_noise(t, v, 1.0, 5), sample_std({1, 0, 1, 0, 1}), 1e-12);
  EXPECT_FALSE(std::isfinite(window_noise(t, v, 1.0, 6)));  // shorter than 6 windows
  NumericalUncertainty n;
  EXPECT_FALSE(n.total());
  n.ensemble = 0.3;
  n.members = 4;
  n.window = 0.4;
  // Both 1σ parts at 95 % (k = 2): sqrt(0.6² + 0.8²) = 2 · 0.5 = 1.0.
  EXPECT_NEAR(*n.total(), 1.0, 1e-12);
  // A Δt part (already 95 %) and a part in words count as given: sqrt(1.0² + 1.2² + 1.6²) = 2.2.
  n.dt = RefinementUncertainty{};
  n.dt->u = 1.2;
  n.other_value = 1.6;
  EXPECT_NEAR(*n.total(), std::sqrt(1.0 + 1.44 + 2.56), 1e-12);
  EXPECT_NE(n.describe().find("ensemble of 4: s 0.3"), std::string::npos) << n.describe();
}

TEST(ReferenceData, CheckerPassesWithinToleranceFailsOutsideAndSkipsWhatDidNotRun) {
  const std::vector<ReferenceRow> rows = {
      {"a", "quantity a", 10.0, "um", 0.5, "abs", "number", "Fig. 1", "r", ""},
      {"b", "quantity b", 2.0, "", 0.01, "rel", "number", "Fig. 1", "r", ""},
      {"c", "claim c", std::nullopt, "", 0, "claim", "claim", "Fig. 2", "r", ""},
      {"d", "not measured", 1.0, "", 0.1, "abs", "number", "Fig. 3", "r", ""},
  };
  std::ostringstream out;
  std::map<std::string, Measured> ours = {{"a", measured(10.4)}, {"b", measured(2.03)}, {"c", {{}, true, ""}}};
  const CheckSummary s = check_against_reference(rows, ours, out);
  EXPECT_EQ(s.passed, 2);
  EXPECT_EQ(s.failed, 1);  // b is 1.5 % off, tolerance 1 %
  EXPECT_EQ(s.not_run, 1);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(out.str().find("FAIL"), std::string::npos);
}

TEST(ReferenceData, RecordedDeviationWithItsCauseShownIsADeviationInsideItsBandAndAFailureOutsideIt) {
  const std::vector<ReferenceRow> rows = {{"re", "Re with a cell", 0.5, "", 0.01, "rel", "number", "Sec. 3", "r", ""}};
  const std::map<std::string, KnownDeviation> dev = {{"re", {"re", 0.52, 0.519, 0.521, "study", "cause", "evidence", "run x"}}};
  // Outside the study's 1 %, inside our own band, the cause shown: a DEVIATION, not a failure.
  CheckSummary s = compare_with_reference(rows, {{"re", measured(0.5205)}}, dev, true);
  EXPECT_EQ(s.deviations, 1);
  EXPECT_EQ(s.failed, 0);
  EXPECT_TRUE(s.ok());
  EXPECT_EQ(s.rows[0].note.substr(0, 5), "cause");
  EXPECT_NE(s.rows[0].note.find("Shown by: run x"), std::string::npos) << s.rows[0].note;
  EXPECT_EQ(s.rows[0].difference, "+0.0205");  // the distance to the study stays visible
  // The code moved the result out of the recorded band: a FAIL, though it is a known deviation.
  s = compare_with_reference(rows, {{"re", measured(0.523)}}, dev, true);
  EXPECT_EQ(s.failed, 1);
  EXPECT_FALSE(s.ok());
  // Within the study's tolerance: a PASS (with a note that the record is stale).
  s = compare_with_reference(rows, {{"re", measured(0.502)}}, dev, true);
  EXPECT_EQ(s.passed, 1);
  EXPECT_FALSE(s.rows[0].note.empty());
  // Not recorded and outside the tolerance: a FAIL.
  s = compare_with_reference(rows, {{"re", measured(0.5205)}}, {}, true);
  EXPECT_EQ(s.failed, 1);
}

TEST(ReferenceData, RecordedDeviationWhoseCauseNoRunShowsIsUnexplainedAndNotAFailure) {
  // The same record without the run or arithmetic that shows its cause: believed, not shown.
  const std::vector<ReferenceRow> rows = {{"re", "Re with a cell", 0.5, "", 0.01, "rel", "number", "Sec. 3", "r", ""}};
  const std::map<std::string, KnownDeviation> dev = {{"re", {"re", 0.52, 0.519, 0.521, "study", "cause", "evidence", ""}}};
  CheckSummary s = compare_with_reference(rows, {{"re", measured(0.5205)}}, dev, true);
  EXPECT_EQ(s.unexplained, 1);
  EXPECT_EQ(s.deviations, 0);
  EXPECT_TRUE(s.ok());
  EXPECT_EQ(s.rows[0].verdict, Verdict::Unexplained);
  EXPECT_NE(s.rows[0].note.find("cause not shown"), std::string::npos) << s.rows[0].note;
  EXPECT_EQ(compare_with_reference(rows, {{"re", measured(0.523)}}, dev, true).failed, 1);  // left its band
}

TEST(ReferenceData, RowMeasuredUnderReadingsIsComparedAtTheChosenReadingAndKeepsThemAll) {
  const std::vector<ReferenceRow> rows = {{"re", "Re with a cell", 0.5, "", 0.002, "abs", "number", "Sec. 3", "r", ""}};
  Measured m = measured(0.51);
  m.readings = {{"p1_mean", 0.51}, {"nodal_mean", 0.501}};
  // No reading chosen: the row's own value (outside); the nodal reading chosen: inside.
  EXPECT_EQ(compare_with_reference(rows, {{"re", m}}, {}, true).failed, 1);
  CheckSummary s = compare_with_reference(rows, {{"re", m}}, {}, true, "nodal_mean");
  EXPECT_EQ(s.passed, 1);
  EXPECT_EQ(s.rows[0].readings, "p1_mean=0.51;nodal_mean=0.501");
  EXPECT_NE(s.rows[0].how.find("nodal_mean"), std::string::npos) << s.rows[0].how;
}

TEST(ReferenceData, ReadingsTableHasOneChosenReadingAtMostAndRejectsABadOne) {
  const auto readings = load_readings(readings_path());
  EXPECT_GE(readings.size(), 4u);
  EXPECT_LE(std::count_if(readings.begin(), readings.end(), [](const Reading& r) { return r.chosen; }), 1);
  const auto path = std::filesystem::temp_directory_path() / "rbcflow_bad_readings.csv";
  std::ofstream(path) << "id,label,chosen,note\n" << "a,U one way,yes,\n" << "b,U another,yes,\n";
  try {
    load_readings(path.string());
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();
  }
}

TEST(ReferenceData, DeviationRecordedAtTheStudysParametersDoesNotCoverAQuickRun) {
  const std::vector<ReferenceRow> rows = {{"re", "Re with a cell", 0.5, "", 0.01, "rel", "number", "Sec. 3", "r", ""}};
  std::map<std::string, KnownDeviation> dev = {{"re", {"re", 0.52, 0.519, 0.521, "study", "cause", "evidence", "run x"}}};
  EXPECT_EQ(compare_with_reference(rows, {{"re", measured(0.52)}}, dev, false).failed, 1);
  dev["re"].applies = "any";
  EXPECT_EQ(compare_with_reference(rows, {{"re", measured(0.52)}}, dev, false).deviations, 1);
}

TEST(ReferenceData, ClaimRecordedAsNotHoldingIsADeviationAndAHoldingClaimPasses) {
  const std::vector<ReferenceRow> rows = {{"c", "a claim", std::nullopt, "", 0, "claim", "claim", "Fig. 5", "r", ""}};
  const std::map<std::string, KnownDeviation> dev = {{"c", {"c", {}, {}, {}, "study", "cause", "evidence", "run x"}}};
  EXPECT_EQ(compare_with_reference(rows, {{"c", {{}, false, ""}}}, dev, true).deviations, 1);
  EXPECT_EQ(compare_with_reference(rows, {{"c", {{}, true, ""}}}, dev, true).passed, 1);
  EXPECT_EQ(compare_with_reference(rows, {{"c", {{}, false, ""}}}, {}, true).failed, 1);
}

TEST(ReferenceData, EveryKnownDeviationNamesARowItsValueLiesInItsBandAndItHasCauseAndEvidence) {
  for (const char* name : {"channel_flow", "single_cell_migration", "four_cells_vs_disks", "cell_free_layer", "constriction"}) {
    const auto rows = load_reference_table(reference_table_path(name));
    for (const auto& [id, d] : load_known_deviations(known_deviations_path(name))) {  // the loader checks band, cause, evidence
      const auto row = std::find_if(rows.begin(), rows.end(), [&](const ReferenceRow& r) { return r.id == id; });
      ASSERT_NE(row, rows.end()) << name << ": " << id;
      // A recorded deviation is outside the study's tolerance (else it is no deviation).
      if (d.ours) {
        const double allowed = row->tolerance_type == "rel" ? row->tolerance * std::abs(*row->value) : row->tolerance;
        EXPECT_GT(std::abs(*d.ours - *row->value), allowed) << name << ": " << id;
      }
    }
  }
}

TEST(RecordedUncertainty, EvidenceRunsWriteTheCompleteRowsAndTheStudysRunsTakeThemBack) {
  // make evidence: rows with a complete u_num are written; an incomplete one and a claim are not.
  std::map<std::string, Measured> evidence = {{"a", measured(9.2, 0.13)}, {"b", measured(0.52, 0.002)}, {"c", measured(1.0, 0.5)}};
  evidence["a"].converged_in_h = "h -> 0 gives 9.1";
  evidence["c"].u.missing = "the ensemble";
  evidence["claim"] = Measured{std::nullopt, true, ""};
  const auto path = (std::filesystem::temp_directory_path() / "rbcflow_uncertainty.csv").string();
  write_measured_uncertainty(evidence, path);
  auto record = load_recorded_uncertainty(path);
  ASSERT_EQ(record.size(), 2u);
  EXPECT_NEAR(record.at("a").u_num(), 0.13, 1e-12);
  EXPECT_EQ(record.at("a").converged_in_h, "h -> 0 gives 9.1");
  record.at("a").commit = "abc1234";
  // make reproduce: the study's run alone (u incomplete) takes the record; a row measured in full
  // keeps its own; a row the record lacks stays unmeasured.
  std::map<std::string, Measured> study = {{"a", measured(9.25, 0.01)}, {"b", measured(0.53, 0.004)}, {"c", measured(1.1, 0.01)}};
  study["a"].u.missing = "the Δt sequence";
  study["c"].u.missing = "the ensemble";
  EXPECT_EQ(apply_recorded_uncertainty(study, record), 1);
  EXPECT_NEAR(*study.at("a").u.total(), 0.13, 1e-12);
  EXPECT_TRUE(study.at("a").u.missing.empty());
  EXPECT_NE(study.at("a").u.describe().find("abc1234"), std::string::npos) << study.at("a").u.describe();
  EXPECT_EQ(study.at("a").converged_in_h, "h -> 0 gives 9.1");
  EXPECT_NEAR(*study.at("b").u.total(), 0.004, 1e-12);
  EXPECT_FALSE(study.at("c").u.missing.empty());
}

TEST(RecordedUncertainty, BadRecordIsRejectedNamingTheLineAndEveryCommittedRecordNamesRowsOfItsTable) {
  const auto path = (std::filesystem::temp_directory_path() / "rbcflow_bad_uncertainty.csv").string();
  const std::string header = "id,dt_values,dt_ratio,dt_formal,dt_reported,dt_noise,dt_label,ensemble,members,window,other,other_value,converged_in_h,source,commit,code\n";
  for (const char* bad : {"a,,,,,,,-0.1,4,,,,,,c,k\n",       // a negative spread
                          "a,9.1 x,2,1,0,,dt,,,,,,,,c,k\n",  // a level that is no number
                          "a,9.1,2,1,0,,dt,,,,,,,,c,k\n",    // one level: no Δt part
                          "a,,,,,,,,,,,,,,c,k\n"}) {         // no part at all
    std::ofstream(path) << header << bad;
    try {
      load_recorded_uncertainty(path);
      FAIL() << "expected an error for " << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(":2:"), std::string::npos) << e.what();
    }
  }
  for (const char* name : {"channel_flow", "single_cell_migration", "four_cells_vs_disks", "cell_free_layer", "constriction", "disk_validation"}) {
    const auto rows = load_reference_table(reference_table_path(name));
    for (const auto& [id, r] : load_recorded_uncertainty(recorded_uncertainty_path(name))) {
      EXPECT_TRUE(std::any_of(rows.begin(), rows.end(), [&](const ReferenceRow& row) { return row.id == id; }))
          << recorded_uncertainty_path(name) << ": '" << id << "' is not a row of " << name;
      EXPECT_FALSE(r.commit.empty()) << recorded_uncertainty_path(name) << ": '" << id << "' names no commit";
    }
  }
}

TEST(RecordedUncertainty, ARecordKeepsTheLevelsAndItsUNumIsTodaysEstimateOfThem) {
  // make evidence writes the Δt levels, the spreads and the named part; read back, the Δt part is
  // estimated again (the same U as measured) and the total is at 95 % (2 s, 2 u_w).
  Measured m = measured(9.156);
  m.u.other_value.reset();
  m.u.ensemble = 0.023;
  m.u.members = 4;
  m.u.window = 0.001;
  m.u.dt = grid_convergence_index({9.115, 9.156, 9.199}, 2.0, 1.0, 1, 0.023);
  m.u.dt->label = "dt 0.75/1.5/3 us";
  const auto path = (std::filesystem::temp_directory_path() / "rbcflow_levels.csv").string();
  write_measured_uncertainty({{"d", m}}, path);
  const auto record = load_recorded_uncertainty(path);
  ASSERT_EQ(record.size(), 1u);
  const NumericalUncertainty& u = record.at("d").parts;
  ASSERT_TRUE(u.dt);
  EXPECT_EQ(u.dt->values, (std::vector<double>{9.115, 9.156, 9.199}));
  EXPECT_EQ(u.dt->reported, 1);
  EXPECT_NEAR(u.dt->u, m.u.dt->u, 1e-12);
  EXPECT_EQ(u.dt->label, "dt 0.75/1.5/3 us");
  EXPECT_NEAR(record.at("d").u_num(), std::sqrt(std::pow(m.u.dt->u, 2) + std::pow(2 * 0.023, 2) + std::pow(2 * 0.001, 2)), 1e-12);
}

TEST(ReferenceData, BadDeviationRecordIsRejectedNamingTheLine) {
  const auto path = std::filesystem::temp_directory_path() / "rbcflow_bad_deviation.csv";
  std::ofstream(path) << "id,ours,band_low,band_high,applies,cause,evidence,shown_by\n"
                      << "re,0.52,0.519,0.5195,study,cause,evidence,\n";  // ours outside its own band
  try {
    load_known_deviations(path.string());
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(":2:"), std::string::npos) << e.what();
  }
}

TEST(RegressionRecord, CheckFailsOutsideTheBandOrWhenARowIsMissingAndEveryRecordLoads) {
  const std::vector<RegressionRow> rec = {{"y", "height", 4.0, "um", 1e-8, "rel", "why", "c", "d", "cmd"},
                                          {"d", "drift", 1e-6, "", 1e-12, "abs", "why", "c", "d", "cmd"}};
  std::ostringstream out;
  EXPECT_TRUE(compare_with_record(rec, {{"y", {"", "", 4.0 + 3e-8}}, {"d", {"", "", 1e-6 + 5e-13}}}, out).ok());
  EXPECT_EQ(compare_with_record(rec, {{"y", {"", "", 4.0 + 5e-8}}, {"d", {"", "", 1e-6}}}, out).failed, 1);
  EXPECT_EQ(compare_with_record(rec, {{"y", {"", "", 4.0}}}, out).failed, 1);  // d missing
  EXPECT_EQ(compare_with_record(rec, {{"y", {"", "", NAN}}, {"d", {"", "", 1e-6}}}, out).failed, 1);
  EXPECT_FALSE(compare_with_record(rec, {{"y", {"", "", 4.0}}, {"d", {"", "", 1e-6}}, {"new", {"", "", 1.0}}}, out).ok());  // stale record
  for (const char* name : {"channel_flow", "single_cell_migration", "stability_map"}) {
    const auto rows = load_regression_record(regression_record_path(name));  // every band measured and explained
    EXPECT_FALSE(rows.empty()) << name;
  }
}

TEST(ReferenceData, StudySummaryListsEveryPublishedNumberWithNotRunForExperimentsWithoutResults) {
  const auto dir = std::filesystem::temp_directory_path() / "rbcflow_summary";
  std::filesystem::create_directories(dir / "single_cell_migration");
  std::ofstream(dir / "single_cell_migration" / "check.csv") << "id,ours,verdict,note,u_num,u_parts,converged_in_h,how,tolerance,readings\n"
                                                              << "hct_s055,6.7733,PASS,,1e-05,,,,0.005 %,\n"
                                                              << "hct_s10,12.308,DEVIATION,cause,1e-05,,,,0.005 %,\n"
                                                              << "re_s055,0.5239,UNEXPLAINED,believed,0.0002,,,,0.00025,p1_mean=0.5239;nodal_mean=0.51747\n"
                                                              << "re_s07,0.524,UNRESOLVED,,0.003,,,,0.00025,\n";
  // A section from an older checker (other columns, other verdicts): its rows count as not run.
  std::filesystem::create_directories(dir / "cell_free_layer");
  std::ofstream(dir / "cell_free_layer" / "check.csv") << "id,ours,verdict,note\r\n"
                                                        << "cfl_100,2.448,PASS,\r\n";
  std::ostringstream out;
  write_study_summary({"single_cell_migration", "four_cells_vs_disks", "cell_free_layer", "constriction"}, dir.string(), out);
  const std::string s = out.str();
  // 6 + 10 + 6 + 5 numbers checked, the 2 empirical estimates as context: the study's 29 numbers.
  EXPECT_NE(s.find("(29: 27 checked, 2 printed as context)"), std::string::npos) << s;
  EXPECT_NE(s.find("1 PASS, 1 UNRESOLVED, 1 DEVIATION, 1 UNEXPLAINED, 0 FAIL"), std::string::npos) << s;
  // The rows our numerics cannot decide, and those whose cause is not shown, are listed in the head.
  EXPECT_NE(s.find("Not reproduced because our numerics cannot decide (UNRESOLVED)"), std::string::npos) << s;
  EXPECT_NE(s.find("ours 0.524 ± 0.003, tolerance 0.00025"), std::string::npos) << s;
  EXPECT_NE(s.find("Not reproduced, the cause not shown (UNEXPLAINED)"), std::string::npos) << s;
  // The readings table: each reading's value, a tick within the tolerance, and the count.
  EXPECT_NE(s.find("| 0.5239 | 0.51747 ✓ |"), std::string::npos) << s;
  EXPECT_NE(s.find("p1_mean 0 of 1; nodal_mean 1 of 1;"), std::string::npos) << s;
  EXPECT_NE(s.find("| constriction | mean velocity in the narrow part | 3.33 cm/s | - |  | not run |"), std::string::npos) << s;
  EXPECT_NE(s.find("| cell_free_layer | cell-free layer, 100 cells, last ms before 200 ms | 2.94 um | - (an older checker's check.csv: re-run) |  | not run |"),
            std::string::npos) << s;
}

TEST(ReferenceData, MalformedTableIsRejectedNamingTheLine) {
  const auto path = std::filesystem::temp_directory_path() / "rbcflow_bad_table.csv";
  std::ofstream(path) << "id,quantity,value,unit,tolerance,tolerance_type,kind,source,reason,apart_from\n"
                      << "x,\"q\",abc,um,0.1,abs,number,src,why,\n";
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
  const CheckSummary c = compare_with_reference(load_reference_table(reference_table_path("channel_flow")), res.measured,
                                               load_known_deviations(known_deviations_path("channel_flow")), false,
                                               chosen_reading(load_readings(readings_path())));
  print_comparison(c, table);
  std::printf("%s", table.str().c_str());
  EXPECT_EQ(c.failed, 0);
  // Under the chosen reading of U (the nodal mean with the wall rows) each channel's U and Re are
  // U0 (1 − h²/H²) M/(M + 1): four deviations shown by that arithmetic (reference-data/deviations).
  EXPECT_EQ(c.deviations, 4);
  EXPECT_EQ(c.unexplained, 0);
  // The quick case's own numbers against its committed record.
  EXPECT_EQ(run_regression_check("channel_flow", res.quick_record, p.out_dir, std::cout), 0);
  // The profile is the parabola at the nodes (exact for the 5-point Laplacian), to round-off.
  for (const auto& [name, r] : res.channels) EXPECT_LT(r.profile_error, 1e-9) << name;
}


TEST(ReferenceData, ChaoticRowIsJudgedAsADistributionOfItsMembers) {
  // A layer of 3.0 um, tolerance 7 %: six members around 3.1 with s = 0.1.
  const std::vector<ReferenceRow> rows = {{"cfl", "layer", 3.0, "um", 0.07, "rel", "number", "Sec. 3", "r", ""}};
  auto ensemble = [](std::vector<double> values, double dt_part) {
    Measured m;
    for (std::size_t k = 0; k < values.size(); ++k) m.ensemble.push_back({"seed" + std::to_string(k + 1), values[k]});
    const EnsembleStatistics e = ensemble_statistics(m.ensemble, 0.0);
    m.u.ensemble = e.s;
    m.u.members = int(values.size());
    m.u.of_mean = true;
    m.u.other = "Δt";
    m.u.other_value = dt_part;
    return std::map<std::string, Measured>{{"cfl", m}};
  };
  const std::vector<double> near = {3.0, 3.2, 3.1, 3.0, 3.2, 3.1};  // mean 3.1, s 0.0894
  // z = (3.0 − 3.1) / (s √(7/6)) = −1.03 and |3.1 − 3.0| ≤ 0.21 + u: PASS, the row's value the mean.
  CheckSummary s = compare_with_reference(rows, ensemble(near, 0.01), {}, true);
  EXPECT_EQ(s.passed, 1) << s.rows[0].note;
  EXPECT_EQ(s.rows[0].ours, "3.1");
  const EnsembleStatistics e = ensemble_statistics(ensemble(near, 0)["cfl"].ensemble, 3.0);
  EXPECT_NEAR(e.mean, 3.1, 1e-12);
  EXPECT_NEAR(e.z, -0.1 / (e.s * std::sqrt(7.0 / 6.0)), 1e-12);
  // The same spread around 3.5: z = −5.2, the study's value not a likely member: UNEXPLAINED,
  // never FAIL (no band is recorded for a distribution's mean).
  std::vector<double> far = near;
  for (double& v : far) v += 0.4;
  s = compare_with_reference(rows, ensemble(far, 0.01), {}, true);
  EXPECT_EQ(s.unexplained, 1);
  EXPECT_EQ(s.failed, 0);
  // |z| ≤ 2 within reach, but a spread so wide that the mean's u_num (2 s/√6 = 0.73) exceeds the
  // tolerance (0.21): UNRESOLVED.
  s = compare_with_reference(rows, ensemble({2.0, 3.0, 4.0, 2.5, 3.5, 4.4}, 0.0), {}, true);
  EXPECT_EQ(s.unresolved, 1) << s.rows[0].note;
  // How many members would decide: n (u/T)² = 6 (2 s/√6 / 0.21)² = 4 s²/0.21², u falling as 1/√n.
  const double wide_s = ensemble_statistics(ensemble({2.0, 3.0, 4.0, 2.5, 3.5, 4.4}, 0.0)["cfl"].ensemble, 0.0).s;
  char needed[64];
  std::snprintf(needed, sizeof needed, "about %.2g members would decide", std::ceil(4 * wide_s * wide_s / (0.21 * 0.21)));
  EXPECT_NE(s.rows[0].note.find(needed), std::string::npos) << needed << " | " << s.rows[0].note;
  // |z| ≤ 2 but the mean beyond the tolerance's reach: mean 3.42, s = 0.2, z = −1.94,
  // |m − study| = 0.42 > T + 2 s/√6 = 0.37: UNEXPLAINED.
  s = compare_with_reference(rows, ensemble({3.137, 3.279, 3.42, 3.42, 3.561, 3.703}, 0.0), {}, true);
  EXPECT_EQ(s.unexplained, 1) << s.rows[0].note;
  // The distribution alone decides a study value far outside it, even with the mean's u_num incomplete.
  auto far_incomplete = ensemble(far, 0.01);
  far_incomplete["cfl"].u.missing = "the arrangements at 3 us";
  EXPECT_EQ(compare_with_reference(rows, far_incomplete, {}, true).unexplained, 1);
  // Six members that agree exactly: no spread to judge by.
  s = compare_with_reference(rows, ensemble({3.1, 3.1, 3.1, 3.1, 3.1, 3.1}, 0.01), {}, true);
  EXPECT_EQ(s.unresolved, 1);
  EXPECT_NE(s.rows[0].note.find("agree exactly"), std::string::npos) << s.rows[0].note;
  // Five members: a distribution cannot decide yet.
  s = compare_with_reference(rows, ensemble({3.0, 3.2, 3.1, 3.0, 3.2}, 0.01), {}, true);
  EXPECT_EQ(s.unresolved, 1);
  // A member's value under the chosen reading replaces its own.
  Measured m;
  m.ensemble = {{"a", 1.0, {{"nodal", 2.0}}}, {"b", 3.0}};
  EXPECT_NEAR(ensemble_statistics(m.ensemble, 0, "nodal").mean, 2.5, 1e-12);
  EXPECT_NEAR(ensemble_statistics(m.ensemble, 0).mean, 2.0, 1e-12);
}

}  // namespace
}  // namespace rbc
