#pragma once
// u_num recorded by the evidence runs, read back by the study's runs (issue 41).
//
// A row's u_num comes from runs beside the one it reports: the Δt sequence, the start ensemble,
// the 2h run (reference/uncertainty.hpp). Those runs are many times the cost of the study's own,
// so the two are split:
//   make evidence   runs them all; each experiment's --check then writes every row whose u_num
//                   is complete to <out>/uncertainty.csv, and the target copies it to
//                   reference-data/uncertainty/<table>.csv with the commit and the code it ran
//                   (the tree of lib/ and experiments/: "code");
//   make reproduce  runs the study's runs only; a row whose evidence runs are not on disk takes
//                   its u_num (all parts, and the h column) from that record, and says so.
// A recorded u_num applies to the code it was measured on: the report states whether the code
// has changed since (reference-data/uncertainty/README.md).
//
// File columns: id, u_num (the row's unit), u_parts, converged_in_h, commit, code.
#include <map>
#include <string>

#include "reference/reference_table.hpp"

namespace rbc {

struct RecordedUncertainty {
  double u_num = 0;
  std::string parts, converged_in_h, commit, code;
};

// reference-data/uncertainty/<table>.csv of the source tree.
std::string recorded_uncertainty_path(const std::string& table);

// The record (an absent file is an empty record); throws std::runtime_error naming the file,
// line and column on bad input.
std::map<std::string, RecordedUncertainty> load_recorded_uncertainty(const std::string& path);

// Writes the rows of `ours` whose u_num is complete (measured, nothing missing) to path with
// empty commit and code columns (make evidence fills them in).
void write_measured_uncertainty(const std::map<std::string, Measured>& ours, const std::string& path);

// Every row of `ours` with a value whose u_num is incomplete and that the record holds takes the
// recorded u_num and h column; returns how many did.
int apply_recorded_uncertainty(std::map<std::string, Measured>& ours, const std::map<std::string, RecordedUncertainty>& record);

}  // namespace rbc
