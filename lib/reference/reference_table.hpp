#pragma once
// The study's published numbers and claims (reference-data/*.csv), the deviations from them we
// know and explain (reference-data/deviations/*.csv), and the comparison table an experiment's
// --check prints: quantity, study, ours, ours − study, tolerance, verdict (the rules:
// reference-data/README.md).
//
// Verdicts, so that CI can act on the table (E = ours − study, T the tolerance, u = our
// numerical uncertainty u_num, reference/uncertainty.hpp):
//   PASS       |E| ≤ T and u ≤ T: within the tolerance fixed before the comparison, and our
//              numerics fine enough to say so;
//   UNRESOLVED u > T (or u not measured) and |E| ≤ T + u: our numerics cannot decide. Counts as
//              not reproduced; never makes --check fail;
//   DEVIATION  outside it (by more than u when u > T), recorded with a band that holds our value,
//              and its cause SHOWN: a named run with the cause removed lands on the study's value
//              within T, or exact arithmetic gives the difference (column shown_by of the record);
//   UNEXPLAINED outside it, recorded with a band that holds our value, but its cause not shown
//              (shown_by empty): what we believe is written beside it; counts as not reproduced;
//   FAIL       outside the tolerance and not recorded, or recorded but outside the recorded band
//              (the code changed the result).
// A chaotic row (a crowd, whose single realisation moves with any change of its start) is judged
// as a distribution instead (Measured::ensemble): the study's value is one realisation, ours the
// n members' mean m and sample standard deviation s, z = (study − m) / (s √(1 + 1/n)) the study's
// distance from our members in units of the spread a new member would have. With n ≥
// kEnsembleMinimum members: where |z| ≤ 2 (the study's value is a likely member of ours) and the
// mean is within the tolerance's reach, |m − study| ≤ T + u (u the mean's u_num: 2 s/√n with the
// Δt part), PASS when u ≤ T and UNRESOLVED when u > T (about n (u/T)² members would decide,
// where u falls as 1/√n); otherwise DEVIATION or UNEXPLAINED as above (never FAIL: no band is
// recorded for a distribution's mean).
// Fewer members: UNRESOLVED. (The rule was set before any ensemble of six had run.)
// The band is where our own value is expected from its measured h/Δt error or ensemble spread,
// not from the distance to the study. Only FAIL makes --check exit 1. A DEVIATION or UNEXPLAINED
// row never hides the distance: study, ours and ours − study are printed on every row, the cause
// (shown or believed) beside it.
// Beside u_num's parts, where the row's Δt levels reach one coarser than the reported run's: the
// u_num a run at that Δt would have against T (the same estimator at that level, from the same
// levels; the ensemble and window parts as measured at the reported Δt): whether the reported Δt
// is larger than the row needs (a reported run's Δt should be the largest whose u_num stays
// within T).
//
// Readings. Where the study's words allow several definitions of a measured quantity (U in
// Re = ρUH/μ is "the averaged velocity in the channel", Section 2), an experiment measures the row
// under each reading from the field (Measured::readings), the report shows them side by side, and
// the one reading chosen for the whole study (reference-data/readings.csv, column chosen) is the
// row's value.
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "reference/uncertainty.hpp"

namespace rbc {

struct ReferenceRow {
  std::string id, quantity;
  std::optional<double> value;  // empty for a claim
  std::string unit;
  double tolerance = 0;
  std::string tolerance_type;  // "abs", "rel" or "claim"
  std::string kind;            // "number", "claim" or "context"
  std::string source, reason;
  std::string value_text;  // the value as the table writes it (the study's digits: 2.710, not 2.71)
  // The ids of the cases the study tells this one apart from: no window may hold their values
  // (column apart_from, space-separated; tested over every table).
  std::vector<std::string> apart_from = {};
};

// Reads one table; throws std::runtime_error naming the file, line and column on bad input.
std::vector<ReferenceRow> load_reference_table(const std::string& path);
// reference-data/<name>.csv of the source tree.
std::string reference_table_path(const std::string& name);

// A deviation from the study we know and explain (reference-data/deviations/<experiment>.csv):
// our value at the study's parameters, the band [low, high] our own value is expected in (the
// row's unit), where the record applies ("study": only at the study's parameters; "any": also in
// the quick CI runs, e.g. geometry), the cause we believe in and the evidence for it. A claim's
// record has no value and no band: it says the claim does not hold for us.
struct KnownDeviation {
  std::string id;
  std::optional<double> ours, low, high;
  std::string applies;  // "study" or "any"
  std::string cause, evidence;
  // The run (case, scene and --set, or the report section holding it) or the exact arithmetic
  // that shows the cause; empty: the cause is believed, not shown, and the row is UNEXPLAINED.
  std::string shown_by = {};
};

// Reads a deviations table (an absent file is an empty table); throws std::runtime_error naming
// the file, line and column on bad input.
std::map<std::string, KnownDeviation> load_known_deviations(const std::string& path);
// reference-data/deviations/<name>.csv of the source tree.
std::string known_deviations_path(const std::string& name);

// What an experiment measured for a row: a number (in the row's unit) or a claim's truth, with
// a short note (e.g. the measured times behind a claim).
// One realisation of a chaotic row: the case that ran it, its value (the row's unit) and its
// value under each reading, the code that made it (empty: the code of this build).
struct EnsembleMember {
  std::string name;
  double value = 0;
  std::vector<std::pair<std::string, double>> readings = {};
  std::string code = {};
};
inline constexpr std::size_t kEnsembleMinimum = 6;

struct Measured {
  std::optional<double> value;
  std::optional<bool> holds;
  std::string note;
  NumericalUncertainty u = {};  // u_num's parts (numbers)
  std::string converged_in_h = {};  // what a finer mesh gives (empty: no h refinement)
  std::string how = {};             // how the row was run: coupling, Δt, pressure form, ...
  // The row's value under each reading of the study's words (reading id, value in the row's unit),
  // each measured from the field; empty for rows no reading touches.
  std::vector<std::pair<std::string, double>> readings = {};
  // A chaotic row's members (above): the row's value is their mean, judged by z.
  std::vector<EnsembleMember> ensemble = {};
};

// The members' values under the reading `chosen` (their own value where it is not measured),
// their mean, sample standard deviation (0 for one member) and z of `study` (NaN when s = 0).
struct EnsembleStatistics {
  std::vector<double> values;
  double mean = 0, s = 0, z = 0;
};
EnsembleStatistics ensemble_statistics(const std::vector<EnsembleMember>& members, double study, const std::string& chosen = "");

// One reading of an ambiguous sentence of the study (reference-data/readings.csv): id, what it
// measures, and whether it is the one chosen for the whole study.
struct Reading {
  std::string id, label;
  bool chosen = false;
  std::string note;
};
// Reads reference-data/readings.csv (or path); at most one reading chosen; throws
// std::runtime_error naming the file, line and column on bad input.
std::vector<Reading> load_readings(const std::string& path);
std::string readings_path();
// The id of the chosen reading ("" when none is).
std::string chosen_reading(const std::vector<Reading>& readings);

enum class Verdict { Pass, Unresolved, Deviation, Unexplained, Fail, NotRun, Context };
// "PASS", "UNRESOLVED", "DEVIATION", "UNEXPLAINED", "FAIL", "not run", "context"
const char* verdict_name(Verdict v);

// One row of a comparison, as printed and as written to check.csv for the report's summary.
struct ComparedRow {
  const ReferenceRow* row = nullptr;
  Verdict verdict = Verdict::NotRun;
  std::string ours, difference, tolerance, study, note;  // formatted; note: the deviation's cause or why it failed
  std::string u_num, u_parts, converged_in_h, how;          // formatted u_num, its parts, the h column, how run
  std::string readings;  // "id=value;id=value" (Measured::readings, full precision)
};

struct CheckSummary {
  int passed = 0, unresolved = 0, deviations = 0, unexplained = 0, failed = 0, not_run = 0;
  std::vector<ComparedRow> rows;
  bool ok() const { return failed == 0; }
};

// Compares; at_study_parameters = false (a quick run) uses only the deviations recorded for
// "any" parameters. A row measured under the reading `chosen` (an id of Measured::readings) is
// compared at that reading's value.
CheckSummary compare_with_reference(const std::vector<ReferenceRow>& rows, const std::map<std::string, Measured>& ours,
                                    const std::map<std::string, KnownDeviation>& deviations, bool at_study_parameters,
                                    const std::string& chosen = "");

// Prints a comparison (plain text, or Markdown when markdown = true) ending with the counts of
// the three verdicts; rows the run did not measure are "not run" and are not failures.
void print_comparison(const CheckSummary& s, std::ostream& out, bool markdown = false);

// The two above with no recorded deviations (tests of the checker itself).
CheckSummary check_against_reference(const std::vector<ReferenceRow>& rows, const std::map<std::string, Measured>& ours,
                                     std::ostream& out, bool markdown = false);

// An experiment's --check: compares with reference-data/<table>.csv and its recorded deviations,
// prints the table on out, writes it as Markdown to <out_dir>/check.md and as CSV to
// <out_dir>/check.csv (for the report), returns the exit code (0, or 1 on a FAIL). At the study's
// parameters it also writes the rows' u_num as measured to <out_dir>/uncertainty.csv, and a row
// whose u_num is incomplete (its evidence runs are not on disk) takes the one recorded in
// reference-data/uncertainty/<table>.csv (reference/recorded_uncertainty.hpp).
int run_reference_check(const std::string& table, const std::map<std::string, Measured>& ours, const std::string& out_dir,
                        std::ostream& out, bool at_study_parameters = true);

// The page a reader opens first: every published number and claim of the experiments named,
// with study, ours, verdict and the experiment that checks it, read from reference-data/ and
// <results_dir>/<experiment>/check.csv (an experiment without one: "not run"). Markdown.
void write_study_summary(const std::vector<std::string>& experiments, const std::string& results_dir, std::ostream& out);

}  // namespace rbc
