#pragma once
// u_num recorded by the evidence runs, read back by the study's runs.
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
// A record keeps the parts' data, not a total: u_num is estimated again from them when read, so
// every recorded row's u_num comes from today's estimator (reference/uncertainty.hpp) at one
// coverage. File columns:
//   id, dt_values (the Δt levels' values, finest first, space-separated, in the row's unit; empty:
//   no Δt part), dt_ratio, dt_formal, dt_reported, dt_noise (the s the estimator was given; empty:
//   none), dt_label, ensemble (1σ; empty: none), members, window (1σ; empty: none), other (a part
//   named in words), other_value, converged_in_h, source (where the parts were read from, when
//   not from that checkout's make evidence), commit (the checkout that ran the runs), code (the
//   id of its sources).
#include <map>
#include <string>

#include "reference/reference_table.hpp"

namespace rbc {

struct RecordedUncertainty {
  NumericalUncertainty parts;  // the Δt part estimated again from its values
  std::string converged_in_h, commit, code, source;
  double u_num() const { return parts.total().value_or(0.0); }
};

// reference-data/uncertainty/<table>.csv of the source tree.
std::string recorded_uncertainty_path(const std::string& table);

// The record (an absent file is an empty record); throws std::runtime_error naming the file,
// line and column on bad input.
std::map<std::string, RecordedUncertainty> load_recorded_uncertainty(const std::string& path);

// Writes the parts of the rows of `ours` whose u_num is complete (measured, nothing missing) to
// path with empty commit, code and source columns (make evidence fills in commit and code).
void write_measured_uncertainty(const std::map<std::string, Measured>& ours, const std::string& path);

// Every row of `ours` with a value whose u_num is incomplete and that the record holds takes the
// recorded parts (its u_num estimated from them) and h column; returns how many did.
int apply_recorded_uncertainty(std::map<std::string, Measured>& ours, const std::map<std::string, RecordedUncertainty>& record);

}  // namespace rbc
