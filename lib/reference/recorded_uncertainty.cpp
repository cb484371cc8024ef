#include "reference/recorded_uncertainty.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "io/csv.hpp"

namespace rbc {

namespace {
const std::vector<std::string> kColumns = {"id", "u_num", "u_parts", "converged_in_h", "commit", "code"};
}

std::string recorded_uncertainty_path(const std::string& table) {
  return std::string(RBCFLOW_SOURCE_DIR) + "/reference-data/uncertainty/" + table + ".csv";
}

std::map<std::string, RecordedUncertainty> load_recorded_uncertainty(const std::string& path) {
  std::map<std::string, RecordedUncertainty> record;
  if (!std::filesystem::exists(path)) return record;
  for (const CsvRecord& rec : read_csv_table(path, kColumns)) {
    const auto& f = rec.fields;
    const double u = csv_number(rec, 1, "u_num");
    if (u < 0) throw std::runtime_error(rec.where + ": column 'u_num' is negative: '" + f[1] + "' (an uncertainty is >= 0)");
    if (!record.emplace(f[0], RecordedUncertainty{u, f[2], f[3], f[4], f[5]}).second)
      throw std::runtime_error(rec.where + ": column 'id': '" + f[0] + "' is recorded twice");
  }
  return record;
}

void write_measured_uncertainty(const std::map<std::string, Measured>& ours, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  for (std::size_t k = 0; k < kColumns.size(); ++k) f << (k ? "," : "") << kColumns[k];
  f << "\n";
  for (const auto& [id, m] : ours) {
    const auto u = m.u.total();
    if (!m.value || !u || !m.u.missing.empty()) continue;
    char v[40];
    std::snprintf(v, sizeof v, "%.6g", *u);
    f << csv_quote(id) << "," << v << "," << csv_quote(m.u.describe()) << "," << csv_quote(m.converged_in_h) << ",,\n";
  }
}

int apply_recorded_uncertainty(std::map<std::string, Measured>& ours, const std::map<std::string, RecordedUncertainty>& record) {
  int applied = 0;
  for (auto& [id, m] : ours) {
    const auto rec = record.find(id);
    if (!m.value || (m.u.total() && m.u.missing.empty()) || rec == record.end()) continue;
    const RecordedUncertainty& r = rec->second;
    m.u = NumericalUncertainty{};
    m.u.other = "recorded at " + (r.commit.empty() ? std::string("an unnamed commit") : r.commit) + " (reference-data/uncertainty: " + r.parts + "), u_num";
    m.u.other_value = r.u_num;
    m.converged_in_h = r.converged_in_h;
    ++applied;
  }
  return applied;
}

}  // namespace rbc
