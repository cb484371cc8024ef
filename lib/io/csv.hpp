#pragma once
// Reading back the numeric CSV files a run writes (series.csv, profile.csv): one column by its
// header name, after the comment lines ('#': the units) that come before the header. Throws
// std::runtime_error naming the file and column.
//
// Reading the text tables of reference-data/ (fields separated by commas; a field may be quoted,
// "a, b", with "" for a quote): every record with the file and line it came from, so that an
// error can name them.
#include <string>
#include <vector>

namespace rbc {

std::vector<double> csv_column(const std::string& path, const std::string& name);
std::vector<std::string> csv_header(const std::string& path);  // the column names

struct CsvRecord {
  std::vector<std::string> fields;
  std::string where;  // "path:line"
};

// The records after the header, which must be `columns`; blank lines are skipped. Throws
// std::runtime_error naming the file and line (missing file, other header, wrong field count,
// unterminated quote).
std::vector<CsvRecord> read_csv_table(const std::string& path, const std::vector<std::string>& columns);
// Field k of a record as a finite number; throws naming the file, line and column.
double csv_number(const CsvRecord& record, std::size_t k, const char* column);
// A field for writing: quoted when it holds a comma, a quote or a line break.
std::string csv_quote(const std::string& field);

}  // namespace rbc
