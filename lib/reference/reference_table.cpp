#include "reference/reference_table.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/csv.hpp"
#include "reference/recorded_uncertainty.hpp"

namespace rbc {

namespace {

const std::vector<std::string> kColumns = {"id", "quantity", "value", "unit", "tolerance",
                                           "tolerance_type", "kind", "source", "reason", "apart_from"};
const std::vector<std::string> kCheckColumns = {"id", "ours", "verdict", "note", "u_num", "u_parts", "converged_in_h", "how", "tolerance", "readings"};
const std::vector<std::string> kDeviationColumns = {"id", "ours", "band_low", "band_high", "applies", "cause", "evidence", "shown_by"};
const std::vector<std::string> kReadingColumns = {"id", "label", "chosen", "note"};

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

// u_num with two significant digits.
std::string fmt_uncertainty(double u) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2g", u);
  return b;
}

bool bold(Verdict v) {
  return v == Verdict::Pass || v == Verdict::Fail || v == Verdict::Deviation || v == Verdict::Unexplained || v == Verdict::Unresolved;
}

// The largest |ours − study| the row's tolerance allows, in the row's unit.
double allowed_difference(const ReferenceRow& r) { return r.tolerance_type == "rel" ? r.tolerance * std::abs(*r.value) : r.tolerance; }

// u_num's parts in words, and the u_num a run one Δt level coarser would have against the
// tolerance (the header's rule): "...; a coarser Δt: at 2 Δt u_num 0.17, above the tolerance" (or
// "within the tolerance: that Δt would do"). No such note where no coarser level was run, u_num is
// incomplete, or the coarser level's Δt part is not finite.
std::string uncertainty_parts(const NumericalUncertainty& u, double allowed) {
  const std::string parts = u.describe();
  if (!u.dt || !u.missing.empty() || u.dt->reported + 1 >= int(u.dt->values.size())) return parts;
  const RefinementUncertainty& d = *u.dt;
  NumericalUncertainty coarser = u;
  coarser.dt = grid_convergence_index(d.values, d.ratio, d.formal_order, d.reported + 1, d.noise);
  const std::optional<double> total = coarser.total();
  if (!std::isfinite(coarser.dt->u) || !total) return parts;
  return parts + "; a coarser Δt: at " + fmt(d.ratio) + " Δt u_num " + fmt_uncertainty(*total) +
         (*total <= allowed ? ", within the tolerance: that Δt would do" : ", above the tolerance");
}

// Measured::readings as one CSV cell, "id=value;id=value", at full precision.
std::string format_readings(const std::vector<std::pair<std::string, double>>& readings) {
  std::string s;
  char b[48];
  for (const auto& [id, v] : readings) {
    std::snprintf(b, sizeof b, "%.9g", v);
    s += (s.empty() ? "" : ";") + id + "=" + b;
  }
  return s;
}

std::vector<std::pair<std::string, double>> parse_readings(const std::string& cell) {
  std::vector<std::pair<std::string, double>> out;
  std::istringstream in(cell);
  for (std::string item; std::getline(in, item, ';');) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) continue;
    out.emplace_back(item.substr(0, eq), std::strtod(item.c_str() + eq + 1, nullptr));
  }
  return out;
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
    case Verdict::Unresolved: return "UNRESOLVED";
    case Verdict::Deviation: return "DEVIATION";
    case Verdict::Unexplained: return "UNEXPLAINED";
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

std::string readings_path() { return std::string(RBCFLOW_SOURCE_DIR) + "/reference-data/readings.csv"; }

std::vector<Reading> load_readings(const std::string& path) {
  std::vector<Reading> out;
  int chosen = 0;
  for (const CsvRecord& rec : read_csv_table(path, kReadingColumns)) {
    const auto& f = rec.fields;
    if (f[2] != "yes" && !f[2].empty()) throw std::runtime_error(rec.where + ": column 'chosen' must be yes or empty, not '" + f[2] + "'");
    if (f[0].empty() || f[1].empty()) throw std::runtime_error(rec.where + ": a reading needs its id and label");
    for (const Reading& r : out)
      if (r.id == f[0]) throw std::runtime_error(rec.where + ": reading '" + f[0] + "' is listed twice");
    out.push_back({f[0], f[1], f[2] == "yes", f[3]});
    if (out.back().chosen && ++chosen > 1) throw std::runtime_error(rec.where + ": only one reading can be chosen for the whole study");
  }
  return out;
}

std::string chosen_reading(const std::vector<Reading>& readings) {
  for (const Reading& r : readings)
    if (r.chosen) return r.id;
  return "";
}

std::vector<ReferenceRow> load_reference_table(const std::string& path) {
  std::vector<ReferenceRow> rows;
  for (const CsvRecord& rec : read_csv_table(path, kColumns)) {
    const auto& f = rec.fields;
    ReferenceRow r{f[0], f[1], std::nullopt, f[3], 0.0, f[5], f[6], f[7], f[8], f[2]};
    std::istringstream apart(f[9]);
    for (std::string id; apart >> id;) r.apart_from.push_back(id);
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
    KnownDeviation d{f[0], std::nullopt, std::nullopt, std::nullopt, f[4], f[5], f[6], f[7]};
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

EnsembleStatistics ensemble_statistics(const std::vector<EnsembleMember>& members, double study, const std::string& chosen) {
  EnsembleStatistics e;
  for (const EnsembleMember& m : members) {
    double v = m.value;
    for (const auto& [id, value] : m.readings)
      if (id == chosen) v = value;
    e.values.push_back(v);
  }
  const double n = double(e.values.size());
  if (e.values.empty()) return e;
  for (double v : e.values) e.mean += v / n;
  double ss = 0;
  for (double v : e.values) ss += (v - e.mean) * (v - e.mean);
  e.s = e.values.size() > 1 ? std::sqrt(ss / (n - 1)) : 0.0;
  e.z = e.s > 0 ? (study - e.mean) / (e.s * std::sqrt(1 + 1 / n)) : NAN;
  return e;
}

CheckSummary compare_with_reference(const std::vector<ReferenceRow>& rows, const std::map<std::string, Measured>& ours,
                                    const std::map<std::string, KnownDeviation>& deviations, bool at_study_parameters,
                                    const std::string& chosen) {
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
    bool within = false, in_band = false, measured = false, undecided = false;
    if (r.kind == "context") {
      c.verdict = Verdict::Context;
    } else if (it == ours.end() || (!it->second.value && !it->second.holds && it->second.ensemble.empty())) {
      c.verdict = Verdict::NotRun;
    } else if (r.kind == "number" && !it->second.ensemble.empty()) {
      // A chaotic row judged as a distribution (the header's rule).
      const Measured& m = it->second;
      const EnsembleStatistics e = ensemble_statistics(m.ensemble, *r.value, chosen);
      const std::optional<double> u = m.u.missing.empty() ? m.u.total() : std::nullopt;
      const double allowed = allowed_difference(r), distance = std::abs(e.mean - *r.value), u_mean = u.value_or(INFINITY);
      const bool enough = e.values.size() >= kEnsembleMinimum && e.s > 0;
      c.ours = fmt(e.mean);
      c.difference = fmt_difference(e.mean - *r.value);
      c.u_num = u ? fmt_uncertainty(*u) : "not measured";
      c.u_parts = uncertainty_parts(m.u, allowed);
      c.converged_in_h = m.converged_in_h;
      c.how = m.how;
      if (!chosen.empty() && !m.readings.empty()) c.how += std::string(c.how.empty() ? "" : "; ") + "U read as '" + chosen + "' (reference-data/readings.csv)";
      c.readings = format_readings(m.readings);
      char z[200];
      std::snprintf(z, sizeof z, "ensemble of %zu: mean %s, s %s, z = %s", e.values.size(), fmt(e.mean).c_str(), fmt(e.s).c_str(),
                    std::isfinite(e.z) ? fmt_difference(e.z).c_str() : "-");
      const std::string believed =
          known ? (known->shown_by.empty() ? "; believed: " + known->cause : "; " + known->cause + " Shown by: " + known->shown_by + ".") : "";
      const Verdict outside = known && !known->shown_by.empty() ? Verdict::Deviation : Verdict::Unexplained;
      if (e.values.size() < kEnsembleMinimum) {
        c.verdict = Verdict::Unresolved;
        c.note = std::string(z) + ": fewer than " + std::to_string(kEnsembleMinimum) + " members finished, a distribution cannot decide";
      } else if (!enough) {
        c.verdict = Verdict::Unresolved;
        c.note = std::string(z) + ": the members agree exactly (s = 0): no spread to judge the study's value by";
      } else if (std::abs(e.z) > 2) {  // the distribution alone decides
        c.verdict = outside;
        c.note = std::string(z) + ": the study's value is not a likely member of ours" + believed;
      } else if (!u) {
        c.verdict = Verdict::Unresolved;
        c.note = std::string(z) + ": the mean's u_num not measured (" + (m.u.missing.empty() ? std::string("no part") : m.u.missing) + ")";
      } else if (distance <= allowed + u_mean) {
        const bool decided = u_mean <= allowed;
        c.verdict = decided ? Verdict::Pass : Verdict::Unresolved;
        c.note = std::string(z) + ": the study's value a likely member of ours, the mean within the tolerance's reach";
        if (!decided) {
          // Where u is the members' scatter (2 s/√n, and a Δt part read from the members' means as
          // noise) it falls as 1/√n: n (u/T)² members would bring it to the tolerance.
          char needed[160];
          const double members = std::ceil(double(e.values.size()) * (u_mean / allowed) * (u_mean / allowed));
          std::snprintf(needed, sizeof needed, "about %.2g members would decide (n (u/T)²: if u_num falls as 1/√n)", members);
          c.note += "; the mean's u_num " + c.u_num + " is larger than the tolerance: " + needed;
        }
      } else {
        c.verdict = outside;
        c.note = std::string(z) + ": the mean is beyond the tolerance's reach" + believed;
      }
    } else if (r.kind == "number") {
      double v = it->second.value.value_or(NAN);
      c.readings = format_readings(it->second.readings);
      bool read_as_chosen = false;
      for (const auto& [id, value] : it->second.readings)
        if (id == chosen) {
          v = value;
          read_as_chosen = true;
        }
      const double allowed = allowed_difference(r);
      // An incomplete u_num (evidence runs missing) cannot clear a row: it counts as not measured.
      const std::optional<double> u = it->second.u.missing.empty() ? it->second.u.total() : std::nullopt;
      within = std::abs(v - *r.value) <= allowed;
      // Our numerics cannot decide: u_num above the tolerance (or unmeasured), and ours ± u_num
      // reaches into the window. Farther out, the row is outside whatever our error is.
      undecided = (!u || *u > allowed) && std::abs(v - *r.value) <= allowed + u.value_or(INFINITY);
      in_band = known && known->low && *known->low <= v && v <= *known->high;
      c.ours = fmt(v);
      c.difference = fmt_difference(v - *r.value);
      c.u_num = u ? fmt_uncertainty(*u) : it->second.u.total() ? fmt_uncertainty(*it->second.u.total()) + " (incomplete)" : "not measured";
      c.u_parts = uncertainty_parts(it->second.u, allowed);
      c.converged_in_h = it->second.converged_in_h;
      c.how = it->second.how;
      if (read_as_chosen)
        c.how += std::string(c.how.empty() ? "" : "; ") + "U read as '" + chosen + "' (reference-data/readings.csv)";
      else if (!chosen.empty() && !it->second.readings.empty())
        c.how += std::string(c.how.empty() ? "" : "; ") + "the chosen reading '" + chosen + "' not measured on this row: its own value";
      measured = true;
    } else {
      within = it->second.holds.value_or(false);
      in_band = known && !known->ours;  // a claim recorded as not holding for us
      c.ours = within ? "holds" : "does not hold";
      c.how = it->second.how;
      measured = true;
    }
    if (measured) {
      if (undecided) {
        c.verdict = Verdict::Unresolved;
        const bool complete = it->second.u.missing.empty() && it->second.u.total();
        c.note = complete ? "u_num " + c.u_num + " is larger than the tolerance: our numerics cannot decide"
                          : "u_num not measured (evidence runs missing: " + (it->second.u.missing.empty() ? std::string("all") : it->second.u.missing) +
                         "): our numerics cannot decide";
      } else if (within) {
        c.verdict = Verdict::Pass;
        if (known) c.note = "recorded as a deviation, but now within the tolerance: update reference-data/deviations";
      } else if (in_band) {
        c.verdict = known->shown_by.empty() ? Verdict::Unexplained : Verdict::Deviation;
        c.note = known->shown_by.empty() ? "cause not shown; believed: " + known->cause : known->cause + " Shown by: " + known->shown_by + ".";
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
      case Verdict::Unresolved: ++s.unresolved; break;
      case Verdict::Deviation: ++s.deviations; break;
      case Verdict::Unexplained: ++s.unexplained; break;
      case Verdict::Fail: ++s.failed; break;
      case Verdict::NotRun: ++s.not_run; break;
      case Verdict::Context: break;
    }
    s.rows.push_back(c);
  }
  return s;
}

// "ours ± u_num" (a number), or ours (a claim, or no u_num).
std::string ours_with_u(const ComparedRow& c) {
  if (c.u_num.empty()) return c.ours;
  const std::size_t paren = c.ours.find(" (");
  const std::string value = c.ours.substr(0, paren), rest = paren == std::string::npos ? "" : c.ours.substr(paren);
  return value + " ± " + c.u_num + rest;
}

void print_comparison(const CheckSummary& s, std::ostream& out, bool md) {
  char line[640];
  if (md) {
    out << "| quantity | study | ours ± u_num | ours − study | tolerance | verdict | u_num from | converged in h | how run | cause of a deviation, or note | source |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|\n";
  } else {
    std::snprintf(line, sizeof line, "%-60s %12s %12s %9s %10s %10s  %s\n", "quantity", "study", "ours", "± u_num", "ours-study", "tolerance", "verdict");
    out << line;
  }
  for (const ComparedRow& c : s.rows) {
    const ReferenceRow& r = *c.row;
    if (md) {
      const char* b = bold(c.verdict) ? "**" : "";
      out << "| " << md_cell(r.quantity) << " | " << c.study << " | " << md_cell(ours_with_u(c)) << " | " << c.difference << " | " << c.tolerance
          << " | " << b << verdict_name(c.verdict) << b << " | " << md_cell(c.u_parts) << " | " << md_cell(c.converged_in_h) << " | "
          << md_cell(c.how) << " | " << md_cell(c.note) << " | " << md_cell(r.source) << " |\n";
    } else {
      const std::string value = c.ours.substr(0, c.ours.find(" ("));
      std::snprintf(line, sizeof line, "%-60.60s %12s %12s %9s %10s %10s  %s\n", r.quantity.c_str(), c.study.c_str(), value.c_str(),
                    c.u_num.empty() ? "" : ("± " + c.u_num).c_str(), c.difference.c_str(), c.tolerance.c_str(), verdict_name(c.verdict));
      out << line;
      if (!c.note.empty()) out << "    " << (c.verdict == Verdict::Deviation ? "known deviation: " : "") << c.note << "\n";
      if (!c.readings.empty()) out << "    readings: " << c.readings << "\n";
      if (!c.u_parts.empty()) out << "    u_num from: " << c.u_parts << "\n";
      if (!c.how.empty()) out << "    how run: " << c.how << "\n";
    }
  }
  out << (md ? "\n" : "") << s.passed << " PASS, " << s.unresolved << " UNRESOLVED, " << s.deviations << " DEVIATION, " << s.unexplained
      << " UNEXPLAINED, " << s.failed << " FAIL, " << s.not_run << " not run\n";
}

CheckSummary check_against_reference(const std::vector<ReferenceRow>& rows, const std::map<std::string, Measured>& ours,
                                     std::ostream& out, bool markdown) {
  CheckSummary s = compare_with_reference(rows, ours, {}, true);
  print_comparison(s, out, markdown);
  return s;
}

int run_reference_check(const std::string& table, const std::map<std::string, Measured>& measured, const std::string& out_dir,
                        std::ostream& out, bool at_study_parameters) {
  const auto rows = load_reference_table(reference_table_path(table));
  std::filesystem::create_directories(out_dir);
  // u_num: as measured from the evidence runs on disk (written for make evidence's record), else
  // as recorded by make evidence (reference/recorded_uncertainty.hpp).
  std::map<std::string, Measured> ours = measured;
  if (at_study_parameters) {
    write_measured_uncertainty(measured, out_dir + "/uncertainty.csv");
    apply_recorded_uncertainty(ours, load_recorded_uncertainty(recorded_uncertainty_path(table)));
  }
  const auto deviations = load_known_deviations(known_deviations_path(table));
  for (const auto& [id, d] : deviations) {
    bool found = false;
    for (const auto& r : rows) found = found || r.id == id;
    if (!found) throw std::runtime_error(known_deviations_path(table) + ": id '" + id + "' is not a row of " + reference_table_path(table));
  }
  const CheckSummary summary = compare_with_reference(rows, ours, deviations, at_study_parameters, chosen_reading(load_readings(readings_path())));
  if (!at_study_parameters)
    out << "Quick parameters: only the rows that do not depend on them (geometry) are compared with the study here; the "
           "quick case's own numbers are checked against its regression record below.\n";
  print_comparison(summary, out);
  std::ofstream md(out_dir + "/check.md");
  print_comparison(summary, md, true);
  std::ofstream csv(out_dir + "/check.csv");
  for (std::size_t k = 0; k < kCheckColumns.size(); ++k) csv << (k ? "," : "") << kCheckColumns[k];
  csv << "\n";
  for (const ComparedRow& c : summary.rows)
    csv << csv_quote(c.row->id) << "," << csv_quote(c.ours) << "," << verdict_name(c.verdict) << "," << csv_quote(c.note) << ","
        << csv_quote(c.u_num) << "," << csv_quote(c.u_parts) << "," << csv_quote(c.converged_in_h) << "," << csv_quote(c.how) << ","
        << csv_quote(c.tolerance) << "," << csv_quote(c.readings) << "\n";
  return summary.ok() ? 0 : 1;
}

void write_study_summary(const std::vector<std::string>& experiments, const std::string& results_dir, std::ostream& out) {
  int numbers = 0, context = 0, claims = 0;
  std::map<Verdict, int> count;
  std::ostringstream table, unresolved, unexplained;
  // The readings table: every row measured under the readings, each reading's value and whether
  // it lies within the study's tolerance, and how many rows each reading brings inside.
  const std::vector<Reading> readings = load_readings(readings_path());
  std::ostringstream readings_table;
  std::map<std::string, int> inside, measured_under;
  readings_table << "| experiment | quantity | study | tolerance |";
  for (const Reading& r : readings) readings_table << " " << md_cell(r.id) << (r.chosen ? " (chosen)" : "") << " |";
  readings_table << "\n|---|---|---|---|";
  for (std::size_t k = 0; k < readings.size(); ++k) readings_table << "---|";
  readings_table << "\n";
  table << "| experiment | quantity | study | ours ± u_num | tolerance | verdict | how run | source |\n|---|---|---|---|---|---|---|---|\n";
  for (const std::string& exp : experiments) {
    struct Ours { std::string ours, verdict, u_num, how, tolerance, readings; };
    std::map<std::string, Ours> ours;
    const std::string check = results_dir + "/" + exp + "/check.csv";
    std::string header;
    if (std::filesystem::exists(check)) std::getline(std::ifstream(check) >> std::ws, header);
    if (!header.empty() && header.back() == '\r') header.pop_back();  // CSV records end in CRLF
    std::string expected;
    for (const auto& c : kCheckColumns) expected += (expected.empty() ? "" : ",") + c;
    if (!header.empty() && header != expected) {
      // A section written by an older checker (other columns, other verdicts): its rows count as
      // not run until the experiment runs again, and say so.
      for (const ReferenceRow& r : load_reference_table(reference_table_path(exp)))
        ours[r.id] = Ours{"- (an older checker's check.csv: re-run)", r.kind == "context" ? "context" : "not run", "", "", "", ""};
    } else if (!header.empty()) {
      for (const CsvRecord& rec : read_csv_table(check, kCheckColumns)) {
        const auto& f = rec.fields;
        ours[f[0]] = {f[1], f[2], f[4], f[7], f[8], f[9]};
      }
    }
    for (const ReferenceRow& r : load_reference_table(reference_table_path(exp))) {
      (r.kind == "number" ? numbers : r.kind == "context" ? context : claims)++;
      Ours o{"-", r.kind == "context" ? "context" : "not run", "", "", "", ""};
      if (ours.count(r.id)) o = ours.at(r.id);
      if (r.kind != "context")
        for (Verdict v : {Verdict::Pass, Verdict::Unresolved, Verdict::Deviation, Verdict::Unexplained, Verdict::Fail, Verdict::NotRun})
          if (o.verdict == verdict_name(v)) ++count[v];
      ComparedRow c;
      c.ours = o.ours;
      c.u_num = o.u_num;
      const std::string study = study_value(r);
      const bool b = o.verdict != "not run" && o.verdict != "context";
      table << "| " << exp << " | " << md_cell(r.quantity) << " | " << study << " | " << md_cell(ours_with_u(c)) << " | " << o.tolerance
            << " | " << (b ? "**" : "") << o.verdict << (b ? "**" : "") << " | " << md_cell(o.how) << " | " << md_cell(r.source) << " |\n";
      const std::string line = "- " + exp + ": " + md_cell(r.quantity) + " — study " + study + ", ours " +
                               md_cell(ours_with_u(c).substr(0, ours_with_u(c).find(" ("))) + ", tolerance " + o.tolerance + "\n";
      if (o.verdict == "UNRESOLVED") unresolved << line;
      if (o.verdict == "UNEXPLAINED") unexplained << line;
      const auto values = parse_readings(o.readings);
      if (!values.empty() && r.value) {
        const double allowed = allowed_difference(r);
        readings_table << "| " << exp << " | " << md_cell(r.quantity) << " | " << study << " | " << o.tolerance << " |";
        for (const Reading& reading : readings) {
          std::string cell = "—";
          for (const auto& [id, v] : values)
            if (id == reading.id) {
              char text[48];
              std::snprintf(text, sizeof text, "%.5g", v);
              const bool in = std::abs(v - *r.value) <= allowed;
              cell = std::string(text) + (in ? " ✓" : "");
              ++measured_under[reading.id];
              if (in) ++inside[reading.id];
            }
          readings_table << " " << cell << " |";
        }
        readings_table << "\n";
      }
    }
  }
  out << "The study's published numbers (" << numbers + context << ": " << numbers << " checked, " << context
      << " printed as context) and claims (" << claims << "): " << count[Verdict::Pass] << " PASS, " << count[Verdict::Unresolved]
      << " UNRESOLVED, " << count[Verdict::Deviation] << " DEVIATION, " << count[Verdict::Unexplained] << " UNEXPLAINED, "
      << count[Verdict::Fail] << " FAIL, " << count[Verdict::NotRun]
      << " not run. PASS: within the study's tolerance, with our numerical uncertainty u_num no larger than it. UNRESOLVED: u_num "
         "is larger than the tolerance (or not measured) and ours ± u_num reaches the window, so our numerics cannot decide; it "
         "counts as not reproduced. DEVIATION: outside the tolerance, with its cause shown by a named run or exact arithmetic "
         "(beside the row in the experiment's section). UNEXPLAINED: outside the tolerance, the cause not shown (what we believe "
         "is beside the row); it counts as not reproduced. FAIL: a difference nobody recorded, or a recorded one that moved.\n\n";
  if (count[Verdict::Unresolved] > 0) out << "Not reproduced because our numerics cannot decide (UNRESOLVED):\n\n" << unresolved.str() << "\n";
  if (count[Verdict::Unexplained] > 0) out << "Not reproduced, the cause not shown (UNEXPLAINED):\n\n" << unexplained.str() << "\n";
  if (!measured_under.empty()) {
    out << "### Readings of \"the averaged velocity in the channel\"\n\n"
           "The study defines Re = ρUH/μ with U \"the averaged velocity in the channel\" (Section 2). Each reading below is "
           "measured from the computed field on every row it touches (reference-data/readings.csv says what each measures); "
           "✓: within the study's tolerance.\n\n"
        << readings_table.str() << "\nRows each reading brings inside the study's tolerance:";
    for (const Reading& reading : readings)
      if (measured_under.count(reading.id))
        out << " " << reading.id << " " << inside[reading.id] << " of " << measured_under[reading.id] << ";";
    out << "\n\n";
    for (const Reading& reading : readings)
      out << "- `" << reading.id << "`" << (reading.chosen ? " (chosen for the whole study)" : "") << ": " << md_cell(reading.label)
          << (reading.note.empty() ? "" : ". " + md_cell(reading.note)) << "\n";
    out << "\n";
  }
  out << table.str() << "\n";
}

}  // namespace rbc
