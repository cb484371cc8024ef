#include "reference/reference_table.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/csv.hpp"

namespace rbc {

namespace {

const std::vector<std::string> kColumns = {"id", "quantity", "value", "unit", "tolerance",
                                           "tolerance_type", "kind", "source", "reason"};
const std::vector<std::string> kDeviationColumns = {"id", "ours", "band_low", "band_high", "applies", "cause", "evidence"};

std::string fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

// The difference printed with the digits of the study's own value plus two.
std::string fmt_difference(double d) {
  char b[32];
  std::snprintf(b, sizeof b, "%+.3g", d);
  return b;
}

// The study's value with its own digits and unit, or "holds" for a claim.
std::string study_value(const ReferenceRow& r) {
  if (!r.value) return "holds";
  return (r.value_text.empty() ? fmt(*r.value) : r.value_text) + (r.unit.empty() ? "" : " " + r.unit);
}

std::string md_cell(std::string s) {
  for (auto& c : s)
    if (c == '|' || c == '\n') c = c == '|' ? '/' : ' ';
  return s;
}

}  // namespace

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::Pass: return "PASS";
    case Verdict::Deviation: return "DEVIATION";
    case Verdict::Fail: return "FAIL";
    case Verdict::NotRun: return "not run";
    case Verdict::Context: return "context";
  }
  return "?";
}

std::string reference_table_path(const std::string& name) {
  return std::string(RBCFLOW_SOURCE_DIR) + "/reference-data/" + name + ".csv";
}

std::string known_deviations_path(const std::string& name) {
  return std::string(RBCFLOW_SOURCE_DIR) + "/reference-data/deviations/" + name + ".csv";
}

std::vector<ReferenceRow> load_reference_table(const std::string& path) {
  std::vector<ReferenceRow> rows;
  for (const CsvRecord& rec : read_csv_table(path, kColumns)) {
    const auto& f = rec.fields;
    ReferenceRow r{f[0], f[1], std::nullopt, f[3], 0.0, f[5], f[6], f[7], f[8], f[2]};
    if (r.kind != "number" && r.kind != "claim" && r.kind != "context")
      throw std::runtime_error(rec.where + ": kind must be number, claim or context, not '" + r.kind + "'");
    if (r.kind == "number") {
      r.value = csv_number(rec, 2, "value");
      r.tolerance = csv_number(rec, 4, "tolerance");
      if (r.tolerance_type != "abs" && r.tolerance_type != "rel")
        throw std::runtime_error(rec.where + ": a number needs tolerance_type abs or rel");
      if (r.reason.empty()) throw std::runtime_error(rec.where + ": every tolerance needs a reason");
    } else if (r.kind == "context") {
      r.value = csv_number(rec, 2, "value");
    } else if (r.tolerance_type != "claim") {
      throw std::runtime_error(rec.where + ": a claim has tolerance_type claim");
    }
    rows.push_back(r);
  }
  return rows;
}

std::map<std::string, KnownDeviation> load_known_deviations(const std::string& path) {
  std::map<std::string, KnownDeviation> out;
  if (!std::filesystem::exists(path)) return out;
  for (const CsvRecord& rec : read_csv_table(path, kDeviationColumns)) {
    const auto& f = rec.fields;
    KnownDeviation d{f[0], std::nullopt, std::nullopt, std::nullopt, f[4], f[5], f[6]};
    const bool number = !f[1].empty() || !f[2].empty() || !f[3].empty();
    if (number) {
      d.ours = csv_number(rec, 1, "ours");
      d.low = csv_number(rec, 2, "band_low");
      d.high = csv_number(rec, 3, "band_high");
      if (!(*d.low <= *d.ours && *d.ours <= *d.high))
        throw std::runtime_error(rec.where + ": our recorded value must lie in its band [band_low, band_high]");
    }
    if (d.applies != "study" && d.applies != "any")
      throw std::runtime_error(rec.where + ": column 'applies' must be study or any, not '" + d.applies + "'");
    if (d.cause.empty() || d.evidence.empty())
      throw std::runtime_error(rec.where + ": a known deviation needs its cause and its evidence");
    if (out.count(d.id)) throw std::runtime_error(rec.where + ": id '" + d.id + "' is recorded twice");
    out[d.id] = d;
  }
  return out;
}

CheckSummary compare_with_reference(const std::vector<ReferenceRow>& rows, const std::map<std::string, Measured>& ours,
                                    const std::map<std::string, KnownDeviation>& deviations, bool at_study_parameters) {
  CheckSummary s;
  for (const ReferenceRow& r : rows) {
    ComparedRow c;
    c.row = &r;
    c.study = study_value(r);
    c.ours = "-";
    if (r.kind == "number") c.tolerance = r.tolerance_type == "rel" ? fmt(100 * r.tolerance) + " %" : fmt(r.tolerance) + " " + r.unit;
    const auto it = ours.find(r.id);
    const auto dev = deviations.find(r.id);
    const KnownDeviation* known =
        dev != deviations.end() && (at_study_parameters || dev->second.applies == "any") ? &dev->second : nullptr;
    bool within = false, in_band = false, measured = false;
    if (r.kind == "context") {
      c.verdict = Verdict::Context;
    } else if (it == ours.end() || (!it->second.value && !it->second.holds)) {
      c.verdict = Verdict::NotRun;
    } else if (r.kind == "number") {
      const double v = it->second.value.value_or(NAN);
      const double allowed = r.tolerance_type == "rel" ? r.tolerance * std::abs(*r.value) : r.tolerance;
      within = std::abs(v - *r.value) <= allowed;
      in_band = known && known->low && *known->low <= v && v <= *known->high;
      c.ours = fmt(v);
      c.difference = fmt_difference(v - *r.value);
      measured = true;
    } else {
      within = it->second.holds.value_or(false);
      in_band = known && !known->ours;  // a claim recorded as not holding for us
      c.ours = within ? "holds" : "does not hold";
      measured = true;
    }
    if (measured) {
      if (within) {
        c.verdict = Verdict::Pass;
        if (known) c.note = "recorded as a deviation, but now within the tolerance: update reference-data/deviations";
      } else if (in_band) {
        c.verdict = Verdict::Deviation;
        c.note = known->cause;
        if (known->low) c.note += " [ours expected in " + fmt(*known->low) + " .. " + fmt(*known->high) + "]";
      } else {
        c.verdict = Verdict::Fail;
        if (known && known->low)
          c.note = "left the band of its recorded deviation (" + fmt(*known->low) + " .. " + fmt(*known->high) + ", recorded " +
                   fmt(*known->ours) + "): the code changed the result";
        else if (known)
          c.note = "recorded as a deviation of a claim, but a value was measured";
      }
    }
    if (it != ours.end() && !it->second.note.empty()) c.ours += " (" + it->second.note + ")";
    switch (c.verdict) {
      case Verdict::Pass: ++s.passed; break;
      case Verdict::Deviation: ++s.deviations; break;
      case Verdict::Fail: ++s.failed; break;
      case Verdict::NotRun: ++s.not_run; break;
      case Verdict::Context: break;
    }
    s.rows.push_back(c);
  }
  return s;
}

void print_comparison(const CheckSummary& s, std::ostream& out, bool md) {
  char line[640];
  if (md) {
    out << "| quantity | study | ours | ours − study | tolerance | verdict | cause of a deviation, or note | source |\n"
           "|---|---|---|---|---|---|---|---|\n";
  } else {
    std::snprintf(line, sizeof line, "%-64s %12s %12s %10s %10s  %s\n", "quantity", "study", "ours", "ours-study", "tolerance", "verdict");
    out << line;
  }
  for (const ComparedRow& c : s.rows) {
    const ReferenceRow& r = *c.row;
    if (md) {
      out << "| " << md_cell(r.quantity) << " | " << c.study << " | " << md_cell(c.ours) << " | " << c.difference << " | " << c.tolerance
          << " | " << (c.verdict == Verdict::Pass || c.verdict == Verdict::Fail || c.verdict == Verdict::Deviation ? "**" : "")
          << verdict_name(c.verdict)
          << (c.verdict == Verdict::Pass || c.verdict == Verdict::Fail || c.verdict == Verdict::Deviation ? "**" : "") << " | "
          << md_cell(c.note) << " | " << md_cell(r.source) << " |\n";
    } else {
      std::snprintf(line, sizeof line, "%-64.64s %12s %12s %10s %10s  %s\n", r.quantity.c_str(), c.study.c_str(), c.ours.c_str(),
                    c.difference.c_str(), c.tolerance.c_str(), verdict_name(c.verdict));
      out << line;
      if (!c.note.empty()) out << "    " << (c.verdict == Verdict::Deviation ? "known deviation: " : "") << c.note << "\n";
    }
  }
  out << (md ? "\n" : "") << s.passed << " PASS, " << s.deviations << " DEVIATION, " << s.failed << " FAIL, " << s.not_run
      << " not run\n";
}

CheckSummary check_against_reference(const std::vector<ReferenceRow>& rows, const std::map<std::string, Measured>& ours,
                                     std::ostream& out, bool markdown) {
  CheckSummary s = compare_with_reference(rows, ours, {}, true);
  print_comparison(s, out, markdown);
  return s;
}

int run_reference_check(const std::string& table, const std::map<std::string, Measured>& ours, const std::string& out_dir,
                        std::ostream& out, bool at_study_parameters) {
  const auto rows = load_reference_table(reference_table_path(table));
  const auto deviations = load_known_deviations(known_deviations_path(table));
  for (const auto& [id, d] : deviations) {
    bool found = false;
    for (const auto& r : rows) found = found || r.id == id;
    if (!found) throw std::runtime_error(known_deviations_path(table) + ": id '" + id + "' is not a row of " + reference_table_path(table));
  }
  const CheckSummary summary = compare_with_reference(rows, ours, deviations, at_study_parameters);
  if (!at_study_parameters)
    out << "Quick parameters: only the rows that do not depend on them (geometry) are compared with the study here; the "
           "quick case's own numbers are checked against its regression record below.\n";
  print_comparison(summary, out);
  std::filesystem::create_directories(out_dir);
  std::ofstream md(out_dir + "/check.md");
  print_comparison(summary, md, true);
  std::ofstream csv(out_dir + "/check.csv");
  csv << "id,ours,verdict,note\n";
  for (const ComparedRow& c : summary.rows)
    csv << csv_quote(c.row->id) << "," << csv_quote(c.ours) << "," << verdict_name(c.verdict) << "," << csv_quote(c.note) << "\n";
  return summary.ok() ? 0 : 1;
}

void write_study_summary(const std::vector<std::string>& experiments, const std::string& results_dir, std::ostream& out) {
  int numbers = 0, context = 0, claims = 0;
  std::map<Verdict, int> count;
  std::ostringstream table;
  table << "| experiment | quantity | study | ours | verdict | source |\n|---|---|---|---|---|---|\n";
  for (const std::string& exp : experiments) {
    std::map<std::string, std::pair<std::string, std::string>> ours;  // id -> (ours, verdict)
    const std::string check = results_dir + "/" + exp + "/check.csv";
    const bool ran = std::filesystem::exists(check);
    if (ran)
      for (const CsvRecord& rec : read_csv_table(check, {"id", "ours", "verdict", "note"}))
        ours[rec.fields[0]] = {rec.fields[1], rec.fields[2]};
    for (const ReferenceRow& r : load_reference_table(reference_table_path(exp))) {
      (r.kind == "number" ? numbers : r.kind == "context" ? context : claims)++;
      std::string mine = "-", verdict = r.kind == "context" ? "context" : "not run";
      if (ours.count(r.id)) std::tie(mine, verdict) = ours.at(r.id);
      if (r.kind != "context")
        for (Verdict v : {Verdict::Pass, Verdict::Deviation, Verdict::Fail, Verdict::NotRun})
          if (verdict == verdict_name(v)) ++count[v];
      const std::string study = study_value(r);
      const bool bold = verdict == "PASS" || verdict == "DEVIATION" || verdict == "FAIL";
      table << "| " << exp << " | " << md_cell(r.quantity) << " | " << study << " | " << md_cell(mine) << " | " << (bold ? "**" : "")
            << verdict << (bold ? "**" : "") << " | " << md_cell(r.source) << " |\n";
    }
  }
  out << "The study's published numbers (" << numbers + context << ": " << numbers << " checked, " << context
      << " printed as context) and claims (" << claims << "): " << count[Verdict::Pass] << " PASS, " << count[Verdict::Deviation]
      << " DEVIATION, " << count[Verdict::Fail] << " FAIL, " << count[Verdict::NotRun]
      << " not run. A DEVIATION is a recorded, explained difference (its cause is beside the row in the experiment's "
         "section); FAIL is a difference nobody explained, or a recorded one that moved.\n\n"
      << table.str() << "\n";
}

}  // namespace rbc
