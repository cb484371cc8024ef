#pragma once
// A quick case's own numbers against the committed record of that same quick case
// (reference-data/regression/<experiment>_quick.csv), the way regression suites of IBAMR and
// HemoCell compare against stored outputs: every experiment has a quick case (seconds to a
// minute) that `make test` runs, so that a change of the physics turns CI red although the
// full-length rows are only checked by `make reproduce`.
//
// A record row holds the value, the band it may move within, the reason for that band (its
// measured round-off and thread-count variation, never the distance to the study), and the
// command, commit and date that produced the value. Verdicts: PASS within the band, FAIL outside
// it or when the quick case no longer produces the row.
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace rbc {

// A number the quick case produced, for its regression record.
struct Observed {
  std::string quantity, unit;
  double value = 0;
};

struct RegressionRow {
  std::string id, quantity;
  double value = 0;
  std::string unit;
  double band = 0;        // allowed |ours − value| (abs) or |ours − value| / |value| (rel)
  std::string band_type;  // "abs" or "rel"
  std::string band_reason, commit, date, command;
};

// reference-data/regression/<experiment>_quick.csv of the source tree.
std::string regression_record_path(const std::string& experiment);
// Throws std::runtime_error naming the file, line and column on bad input or a missing band.
std::vector<RegressionRow> load_regression_record(const std::string& path);

struct RegressionSummary {
  int passed = 0, failed = 0, unrecorded = 0;
  bool ok() const { return failed == 0 && unrecorded == 0; }
};

// Compares and prints (plain text, or Markdown): quantity, recorded, ours, ours − recorded, band,
// verdict. A value without a record row is "not recorded" and fails too: the record is stale.
RegressionSummary compare_with_record(const std::vector<RegressionRow>& record, const std::map<std::string, Observed>& ours,
                                      std::ostream& out, bool markdown = false);

// An experiment's --quick --check: compares with the experiment's record, prints on out, writes
// Markdown to <out_dir>/regression.md; returns 0, or 1 on a FAIL.
int run_regression_check(const std::string& experiment, const std::map<std::string, Observed>& ours, const std::string& out_dir,
                         std::ostream& out);

// --record-regression: writes the record anew from this run's values, keeping each row's band and
// its reason (a new row gets an empty band, which the loader refuses until a measured band is
// written in), with the command, the source tree's commit and today's date.
void write_regression_record(const std::string& experiment, const std::map<std::string, Observed>& ours, const std::string& command);

// What an experiment's main does with its quick record: --record-regression (quick runs only)
// writes it anew, --quick --check compares with it. Returns 0, or 1 on a FAIL; throws
// std::invalid_argument for --record-regression without --quick.
int handle_quick_record(const std::string& experiment, const std::map<std::string, Observed>& ours, bool quick, bool record,
                        bool check, const std::string& out_dir, std::ostream& out);

}  // namespace rbc
