#include "reference/regression_record.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "io/csv.hpp"

namespace rbc {

namespace {

const std::vector<std::string> kColumns = {"id", "quantity", "value", "unit", "band", "band_type",
                                           "band_reason", "commit", "date", "command"};

std::string fmt(double v, const char* f = "%.10g") {
  char b[40];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// The commit of the source tree, marked when it has uncommitted changes.
std::string source_commit() {
  const std::string git = "git -C '" + std::string(RBCFLOW_SOURCE_DIR) + "' ";
  auto run = [](const std::string& cmd) {
    std::string out;
    std::unique_ptr<FILE, int (*)(FILE*)> p(popen(cmd.c_str(), "r"), pclose);
    if (!p) return out;
    char buf[256];
    while (std::fgets(buf, sizeof buf, p.get())) out += buf;
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    return out;
  };
  std::string commit = run(git + "rev-parse --short HEAD 2>/dev/null");
  if (commit.empty()) return "unknown";
  if (!run(git + "status --porcelain --untracked-files=no -- lib experiments 2>/dev/null").empty()) commit += "+uncommitted";
  return commit;
}

}  // namespace

std::string regression_record_path(const std::string& experiment) {
  return std::string(RBCFLOW_SOURCE_DIR) + "/reference-data/regression/" + experiment + "_quick.csv";
}

std::vector<RegressionRow> load_regression_record(const std::string& path) {
  std::vector<RegressionRow> rows;
  for (const CsvRecord& rec : read_csv_table(path, kColumns)) {
    const auto& f = rec.fields;
    RegressionRow r{f[0], f[1], csv_number(rec, 2, "value"), f[3], 0.0, f[5], f[6], f[7], f[8], f[9]};
    if (f[4].empty()) throw std::runtime_error(rec.where + ": row '" + r.id + "' has no band yet: measure it and write it in");
    r.band = csv_number(rec, 4, "band");
    if (!(r.band >= 0)) throw std::runtime_error(rec.where + ": column 'band' must be >= 0");
    if (r.band_type != "abs" && r.band_type != "rel") throw std::runtime_error(rec.where + ": column 'band_type' must be abs or rel");
    if (r.band_reason.empty()) throw std::runtime_error(rec.where + ": every band needs its reason (how it was measured)");
    rows.push_back(r);
  }
  return rows;
}

RegressionSummary compare_with_record(const std::vector<RegressionRow>& record, const std::map<std::string, Observed>& ours,
                                      std::ostream& out, bool md) {
  RegressionSummary s;
  char line[512];
  if (md) out << "| quantity | recorded | ours | ours − recorded | band | verdict |\n|---|---|---|---|---|---|\n";
  else {
    std::snprintf(line, sizeof line, "%-60s %16s %16s %11s %10s  %s\n", "quantity (quick case)", "recorded", "ours", "difference", "band",
                  "verdict");
    out << line;
  }
  auto print = [&](const std::string& q, const std::string& rec, const std::string& mine, const std::string& diff, const std::string& band,
                   const char* verdict) {
    if (md) out << "| " << q << " | " << rec << " | " << mine << " | " << diff << " | " << band << " | " << verdict << " |\n";
    else {
      std::snprintf(line, sizeof line, "%-60.60s %16s %16s %11s %10s  %s\n", q.c_str(), rec.c_str(), mine.c_str(), diff.c_str(),
                    band.c_str(), verdict);
      out << line;
    }
  };
  for (const RegressionRow& r : record) {
    const std::string q = r.quantity + (r.unit.empty() ? "" : " (" + r.unit + ")");
    const std::string band = r.band_type == "rel" ? fmt(r.band, "%.1e") + " rel" : fmt(r.band, "%.1e");
    const auto it = ours.find(r.id);
    if (it == ours.end()) {
      ++s.failed;
      print(q, fmt(r.value), "missing", "", band, "FAIL");
      continue;
    }
    const double d = it->second.value - r.value;
    const double allowed = r.band_type == "rel" ? r.band * std::abs(r.value) : r.band;
    const bool pass = std::abs(d) <= allowed;  // false for NaN
    (pass ? s.passed : s.failed)++;
    print(q, fmt(r.value), fmt(it->second.value), fmt(d, "%+.2e"), band, pass ? "PASS" : "FAIL");
  }
  for (const auto& [id, o] : ours) {
    bool recorded = false;
    for (const auto& r : record) recorded = recorded || r.id == id;
    if (recorded) continue;
    ++s.unrecorded;
    print(o.quantity + (o.unit.empty() ? "" : " (" + o.unit + ")"), "-", fmt(o.value), "", "", "FAIL (not recorded)");
  }
  out << (md ? "\n" : "") << s.passed << " PASS, " << s.failed + s.unrecorded << " FAIL against the quick case's regression record";
  if (!record.empty()) out << " (values of commit " << record.front().commit << ", " << record.front().date << ")";
  out << "\n";
  return s;
}

int run_regression_check(const std::string& experiment, const std::map<std::string, Observed>& ours, const std::string& out_dir,
                         std::ostream& out) {
  const auto record = load_regression_record(regression_record_path(experiment));
  const RegressionSummary s = compare_with_record(record, ours, out);
  std::filesystem::create_directories(out_dir);
  std::ofstream md(out_dir + "/regression.md");
  compare_with_record(record, ours, md, true);
  return s.ok() ? 0 : 1;
}

void write_regression_record(const std::string& experiment, const std::map<std::string, Observed>& ours, const std::string& command) {
  const std::string path = regression_record_path(experiment);
  std::map<std::string, CsvRecord> old;
  if (std::filesystem::exists(path))
    for (CsvRecord& rec : read_csv_table(path, kColumns)) old[rec.fields[0]] = rec;
  std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
  const std::string commit = source_commit();
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream o(path);
  for (std::size_t k = 0; k < kColumns.size(); ++k) o << (k ? "," : "") << kColumns[k];
  o << "\n";
  for (const auto& [id, v] : ours) {
    const bool known = old.count(id);
    o << csv_quote(id) << "," << csv_quote(v.quantity) << "," << fmt(v.value, "%.17g") << "," << csv_quote(v.unit) << ","
      << (known ? old[id].fields[4] : "") << "," << (known ? old[id].fields[5] : "rel") << ","
      << csv_quote(known ? old[id].fields[6] : "") << "," << commit << "," << date << "," << csv_quote(command) << "\n";
  }
}

int handle_quick_record(const std::string& experiment, const std::map<std::string, Observed>& ours, bool quick, bool record,
                        bool check, const std::string& out_dir, std::ostream& out) {
  if (record) {
    if (!quick) throw std::invalid_argument("--record-regression records the quick case: add --quick");
    write_regression_record(experiment, ours, "build/bin/" + experiment + " --quick --record-regression");
    out << "wrote " << regression_record_path(experiment) << "\n";
  }
  return quick && check ? run_regression_check(experiment, ours, out_dir, out) : 0;
}

}  // namespace rbc
