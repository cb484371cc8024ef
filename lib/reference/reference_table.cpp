#include "reference/reference_table.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rbc {

namespace {

// One CSV record: fields separated by commas, a field may be quoted ("a, b"; "" is a quote).
std::vector<std::string> split_csv(const std::string& line, const std::string& where) {
  std::vector<std::string> f(1);
  bool quoted = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (quoted) {
      if (c == '"' && k + 1 < line.size() && line[k + 1] == '"') { f.back() += '"'; ++k; }
      else if (c == '"') quoted = false;
      else f.back() += c;
    } else if (c == '"') quoted = true;
    else if (c == ',') f.emplace_back();
    else if (c != '\r') f.back() += c;
  }
  if (quoted) throw std::runtime_error(where + ": unterminated quote");
  return f;
}

const std::vector<std::string> kColumns = {"id", "quantity", "value", "unit", "tolerance",
                                           "tolerance_type", "kind", "source", "reason"};

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

}  // namespace

std::string reference_table_path(const std::string& name) {
  return std::string(RBCFLOW_SOURCE_DIR) + "/reference-data/" + name + ".csv";
}

std::vector<ReferenceRow> load_reference_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the reference table");
  std::string line;
  std::getline(in, line);
  if (split_csv(line, path + ":1") != kColumns)
    throw std::runtime_error(path + ":1: the header must be: id,quantity,value,unit,tolerance,tolerance_type,kind,source,reason");
  std::vector<ReferenceRow> rows;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(n);
    const auto f = split_csv(line, where);
    if (f.size() != kColumns.size()) throw std::runtime_error(where + ": expected 9 fields, found " + std::to_string(f.size()));
    ReferenceRow r{f[0], f[1], std::nullopt, f[3], 0.0, f[5], f[6], f[7], f[8]};
    auto number = [&](const std::string& s, const char* col) {
      try {
        std::size_t used = 0;
        const double v = std::stod(s, &used);
        if (used != s.size() || !std::isfinite(v)) throw std::invalid_argument(s);
        return v;
      } catch (const std::exception&) {
        throw std::runtime_error(where + ": column '" + col + "' is not a number: '" + s + "'");
      }
    };
    if (r.kind != "number" && r.kind != "claim" && r.kind != "context")
      throw std::runtime_error(where + ": kind must be number, claim or context, not '" + r.kind + "'");
    if (r.kind == "number") {
      r.value = number(f[2], "value");
      r.tolerance = number(f[4], "tolerance");
      if (r.tolerance_type != "abs" && r.tolerance_type != "rel")
        throw std::runtime_error(where + ": a number needs tolerance_type abs or rel");
      if (r.reason.empty()) throw std::runtime_error(where + ": every tolerance needs a reason");
    } else if (r.kind == "context") {
      r.value = number(f[2], "value");
    } else if (r.tolerance_type != "claim") {
      throw std::runtime_error(where + ": a claim has tolerance_type claim");
    }
    rows.push_back(r);
  }
  return rows;
}

CheckSummary check_against_reference(const std::vector<ReferenceRow>& rows, const std::map<std::string, Measured>& ours,
                                     std::ostream& out, bool md) {
  CheckSummary s;
  char line[512];
  if (md) out << "| quantity | study | ours | tolerance | verdict | source |\n|---|---|---|---|---|---|\n";
  else {
    std::snprintf(line, sizeof line, "%-72s %12s %12s %14s  %s\n", "quantity", "study", "ours", "tolerance", "verdict");
    out << line;
  }
  for (const ReferenceRow& r : rows) {
    const auto it = ours.find(r.id);
    std::string study = r.value ? fmt(*r.value) + (r.unit.empty() ? "" : " " + r.unit) : "holds";
    std::string tol, mine = "-", verdict;
    if (r.kind == "number") tol = r.tolerance_type == "rel" ? fmt(100 * r.tolerance) + " %" : fmt(r.tolerance) + " " + r.unit;
    if (r.kind == "context") {
      verdict = "context";
    } else if (it == ours.end() || (!it->second.value && !it->second.holds)) {
      verdict = "not run";
      ++s.not_run;
    } else if (r.kind == "number") {
      const double v = it->second.value.value_or(NAN);
      const double allowed = r.tolerance_type == "rel" ? r.tolerance * std::abs(*r.value) : r.tolerance;
      const bool pass = std::abs(v - *r.value) <= allowed;
      mine = fmt(v);
      verdict = pass ? "PASS" : "FAIL";
      (pass ? s.passed : s.failed)++;
    } else {
      const bool pass = it->second.holds.value_or(false);
      mine = pass ? "holds" : "does not hold";
      verdict = pass ? "PASS" : "FAIL";
      (pass ? s.passed : s.failed)++;
    }
    if (it != ours.end() && !it->second.note.empty()) mine += " (" + it->second.note + ")";
    if (md) out << "| " << r.quantity << " | " << study << " | " << mine << " | " << tol << " | " << verdict << " | " << r.source << " |\n";
    else {
      std::snprintf(line, sizeof line, "%-72.72s %12s %12s %14s  %s\n", r.quantity.c_str(), study.c_str(), mine.c_str(),
                    tol.c_str(), verdict.c_str());
      out << line;
    }
  }
  out << (md ? "\n" : "") << s.passed << " passed, " << s.failed << " failed, " << s.not_run << " not run\n";
  return s;
}

int run_reference_check(const std::string& table, const std::map<std::string, Measured>& ours,
                        const std::string& out_dir, std::ostream& out) {
  const auto rows = load_reference_table(reference_table_path(table));
  const CheckSummary summary = check_against_reference(rows, ours, out);
  std::ofstream md(out_dir + "/check.md");
  check_against_reference(rows, ours, md, true);
  return summary.ok() ? 0 : 1;
}

}  // namespace rbc
