#include "reference/recorded_uncertainty.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "io/csv.hpp"

namespace rbc {

namespace {

const std::vector<std::string> kColumns = {"id",       "dt_values", "dt_ratio", "dt_formal",   "dt_reported", "dt_noise",
                                           "dt_label", "ensemble",  "members",  "window",      "other",       "other_value",
                                           "converged_in_h", "source", "commit", "code"};

std::string number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

std::string optional_number(const std::optional<double>& v) { return v && std::isfinite(*v) ? number(*v) : ""; }

// An optional non-negative number of a record (empty: absent).
std::optional<double> optional_field(const CsvRecord& rec, std::size_t k, const char* column) {
  if (rec.fields[k].empty()) return std::nullopt;
  const double v = csv_number(rec, k, column);
  if (v < 0) throw std::runtime_error(rec.where + ": column '" + column + "' is negative: '" + rec.fields[k] + "' (an uncertainty is >= 0)");
  return v;
}

}  // namespace

std::string recorded_uncertainty_path(const std::string& table) {
  return std::string(RBCFLOW_SOURCE_DIR) + "/reference-data/uncertainty/" + table + ".csv";
}

std::map<std::string, RecordedUncertainty> load_recorded_uncertainty(const std::string& path) {
  std::map<std::string, RecordedUncertainty> record;
  if (!std::filesystem::exists(path)) return record;
  for (const CsvRecord& rec : read_csv_table(path, kColumns)) {
    const auto& f = rec.fields;
    RecordedUncertainty r;
    NumericalUncertainty& u = r.parts;
    if (!f[1].empty()) {
      // The Δt part, estimated again from its levels' values.
      std::vector<double> values;
      std::istringstream in(f[1]);
      for (std::string v; in >> v;) {
        CsvRecord one{{v}, rec.where};
        values.push_back(csv_number(one, 0, "dt_values"));
      }
      const double ratio = csv_number(rec, 2, "dt_ratio"), formal = csv_number(rec, 3, "dt_formal");
      const int reported = int(csv_number(rec, 4, "dt_reported"));
      const std::optional<double> noise = optional_field(rec, 5, "dt_noise");
      try {
        u.dt = grid_convergence_index(values, ratio, formal, reported, noise.value_or(NAN));
      } catch (const std::invalid_argument& e) {
        throw std::runtime_error(rec.where + ": the Δt part: " + e.what());
      }
      u.dt->label = f[6];
    }
    u.ensemble = optional_field(rec, 7, "ensemble");
    if (u.ensemble) u.members = int(csv_number(rec, 8, "members"));
    u.window = optional_field(rec, 9, "window");
    u.other = f[10];
    u.other_value = optional_field(rec, 11, "other_value");
    if (!u.total()) throw std::runtime_error(rec.where + ": a record needs at least one part of u_num");
    r.converged_in_h = f[12];
    r.source = f[13];
    r.commit = f[14];
    r.code = f[15];
    if (!record.emplace(f[0], r).second) throw std::runtime_error(rec.where + ": column 'id': '" + f[0] + "' is recorded twice");
  }
  return record;
}

void write_measured_uncertainty(const std::map<std::string, Measured>& ours, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  for (std::size_t k = 0; k < kColumns.size(); ++k) f << (k ? "," : "") << kColumns[k];
  f << "\n";
  for (const auto& [id, m] : ours) {
    if (!m.value || !m.u.total() || !m.u.missing.empty()) continue;
    const NumericalUncertainty& u = m.u;
    std::string values;
    if (u.dt)
      for (double v : u.dt->values) {
        if (!values.empty()) values += ' ';
        values += number(v);
      }
    f << csv_quote(id) << "," << values << "," << (u.dt ? number(u.dt->ratio) : "") << "," << (u.dt ? number(u.dt->formal_order) : "") << ","
      << (u.dt ? std::to_string(u.dt->reported) : "") << "," << (u.dt ? optional_number(u.dt->noise) : "") << ","
      << csv_quote(u.dt ? u.dt->label : "") << "," << optional_number(u.ensemble) << "," << (u.ensemble ? std::to_string(u.members) : "") << ","
      << optional_number(u.window) << "," << csv_quote(u.other) << "," << optional_number(u.other_value) << "," << csv_quote(m.converged_in_h)
      << ",,,\n";
  }
  if (!f) throw std::runtime_error("cannot write " + path);
}

int apply_recorded_uncertainty(std::map<std::string, Measured>& ours, const std::map<std::string, RecordedUncertainty>& record) {
  int applied = 0;
  for (auto& [id, m] : ours) {
    const auto rec = record.find(id);
    if (!m.value || (m.u.total() && m.u.missing.empty()) || rec == record.end()) continue;
    const RecordedUncertainty& r = rec->second;
    m.u = r.parts;
    m.u.provenance = "recorded at " + (r.commit.empty() ? std::string("an unnamed commit") : r.commit) + " (reference-data/uncertainty" +
                     (r.source.empty() ? "" : ": " + r.source) + ")";
    m.converged_in_h = r.converged_in_h;
    ++applied;
  }
  return applied;
}

}  // namespace rbc
