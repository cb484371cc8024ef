#include "io/csv.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rbc {

namespace {
// The header's names of an open numeric CSV file, after its comment lines ('#': the units).
std::vector<std::string> read_header(std::istream& in) {
  std::string line, cell;
  while (std::getline(in, line) && !line.empty() && line[0] == '#') {}
  std::vector<std::string> names;
  std::stringstream hs(line);
  while (std::getline(hs, cell, ',')) names.push_back(cell);
  return names;
}
}  // namespace

std::vector<std::string> csv_header(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  return read_header(in);
}

std::vector<double> csv_column(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  const std::vector<std::string> names = read_header(in);
  const auto at = std::find(names.begin(), names.end(), name);
  if (at == names.end()) throw std::runtime_error(path + ": no column '" + name + "'");
  const int col = int(at - names.begin());
  std::string line, cell;
  std::vector<double> v;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    for (int k = 0; std::getline(ss, cell, ','); ++k)
      if (k == col) { v.push_back(std::stod(cell)); break; }
  }
  return v;
}

namespace {

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

}  // namespace

std::vector<CsvRecord> read_csv_table(const std::string& path, const std::vector<std::string>& columns) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open the table");
  std::string line;
  std::getline(in, line);
  if (split_csv(line, path + ":1") != columns) {
    std::string want;
    for (const auto& c : columns) want += (want.empty() ? "" : ",") + c;
    throw std::runtime_error(path + ":1: the header must be: " + want);
  }
  std::vector<CsvRecord> out;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty() || line == "\r") continue;
    const std::string where = path + ":" + std::to_string(n);
    auto f = split_csv(line, where);
    if (f.size() != columns.size())
      throw std::runtime_error(where + ": expected " + std::to_string(columns.size()) + " fields, found " + std::to_string(f.size()));
    out.push_back({std::move(f), where});
  }
  return out;
}

double csv_number(const CsvRecord& r, std::size_t k, const char* column) {
  const std::string& s = r.fields.at(k);
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size() || !std::isfinite(v)) throw std::invalid_argument(s);
    return v;
  } catch (const std::exception&) {
    throw std::runtime_error(r.where + ": column '" + column + "' is not a number: '" + s + "'");
  }
}

std::string csv_quote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}

}  // namespace rbc
