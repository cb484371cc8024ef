#pragma once
// The study's published numbers and claims (reference-data/*.csv) and the comparison table an
// experiment's --check prints: quantity, study, ours, tolerance, verdict (SPEC section 6).
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace rbc {

struct ReferenceRow {
  std::string id, quantity;
  std::optional<double> value;  // empty for a claim
  std::string unit;
  double tolerance = 0;
  std::string tolerance_type;  // "abs", "rel" or "claim"
  std::string kind;            // "number", "claim" or "context"
  std::string source, reason;
};

// Reads one table; throws std::runtime_error naming the file, line and column on bad input.
std::vector<ReferenceRow> load_reference_table(const std::string& path);
// reference-data/<name>.csv of the source tree.
std::string reference_table_path(const std::string& name);

// What an experiment measured for a row: a number (in the row's unit) or a claim's truth, with
// a short note (e.g. the measured times behind a claim).
struct Measured {
  std::optional<double> value;
  std::optional<bool> holds;
  std::string note;
};

struct CheckSummary {
  int passed = 0, failed = 0, not_run = 0;
  bool ok() const { return failed == 0; }
};

// Prints the comparison table (plain text, or Markdown when markdown = true); rows the run did
// not measure are "not run" and are not failures.
CheckSummary check_against_reference(const std::vector<ReferenceRow>& rows, const std::map<std::string, Measured>& ours,
                                     std::ostream& out, bool markdown = false);

// An experiment's --check: compares with reference-data/<table>.csv, prints the table on out,
// writes it as Markdown to <out_dir>/check.md (for the report), returns the exit code (0, or 1 on
// a failed row).
int run_reference_check(const std::string& table, const std::map<std::string, Measured>& ours,
                        const std::string& out_dir, std::ostream& out);

}  // namespace rbc
